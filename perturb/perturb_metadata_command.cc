// lsds perturb-metadata COLLECTION --sigma POS_M[,ROT_DEG] --seed N [-o FILE]
// [--model M] [...]
// The flag grammar and the printed lines live in perturb/noise_flags.h.
#include <iostream>

#include "perturb/noise_flags.h"
#include "perturb/perturb_collection.h"
#include "tools/command.h"

namespace lsds {

int RunPerturbMetadata(int argc, char** argv) {
  CLI::App app(
      "Write a perturbed copy of a collection's truth metadata (controlled, "
      "reproducible noise with "
      "the realized errors recorded) and register it as a metadata variant. "
      "See "
      "docs/perturb-metadata.md.",
      "lsds perturb-metadata");
  std::string collection, output, sigma, sigma_rot, model = "gaussian", report_path;
  std::vector<std::string> biases;
  double sigma_pos = -1, sigma_alt = -1, sigma_time = 0, sigma_fov = 0, tau = 0;
  uint64_t seed = 0;
  app.add_option("COLLECTION", collection, "collection folder (holds collection.json)")->required();
  app.add_option("--sigma",
                 sigma,
                 "POS_M[,ROT_DEG]: position sigma (horizontal and vertical) in "
                 "metres and attitude "
                 "sigma (every axis) in degrees; the flags below override it");
  auto* pos_flag = app.add_option(
      "--sigma-pos", sigma_pos, "horizontal position sigma per axis (east, north), metres");
  auto* alt_flag = app.add_option("--sigma-alt", sigma_alt, "vertical position sigma (up), metres");
  app.add_option(
      "--sigma-rot", sigma_rot, "attitude sigma in degrees: S (every axis) or ROLL,PITCH,YAW");
  auto* time_flag = app.add_option("--sigma-time", sigma_time, "time-stamp sigma, seconds");
  auto* fov_flag =
      app.add_option("--sigma-fov", sigma_fov, "horizontal field-of-view sigma, degrees");
  app.add_option("--bias",
                 biases,
                 "constant error FIELD=VALUE[,...], repeatable; FIELD: pos "
                 "(E[,N] m), alt (m), rot "
                 "(S or R,P,Y deg), time (s), fov (deg), east, north, up, "
                 "roll, pitch, yaw")
      ->expected(1)  // one value per --bias, so a following COLLECTION is not taken
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app.add_option("--model", model, "noise model: gaussian | uniform | gauss-markov")
      ->capture_default_str();
  app.add_option("--tau", tau, "gauss-markov correlation time, seconds");
  app.add_option("--seed", seed, "random seed; the same seed gives a byte-identical output")
      ->required();
  app.add_option("-o,--output",
                 output,
                 "output metadata file (default "
                 "COLLECTION/metadata.perturbed-<seed>.json)");
  CommonFlags common;
  AddCommonFlags(app,
                 &common,
                 "overwrite an existing output and report",
                 {{"--frames",
                   "a metadata variant covers every frame of the collection (lsds validate "
                   "and the consumers expect one entry per frame)"}});
  auto* report_flag =
      app.add_option("--report",
                     report_path,
                     "measure how far the targets' projected OBB corners move (pixels) "
                     "and write "
                     "the per-frame report (default: the output with .report.json)")
          ->expected(0, 1);
  return RunCommand(app, common, argc, argv, [&] {
    noise::PerturbOptions options;
    options.collection = collection;
    options.output = output;
    options.force = common.force;
    options.report = report_flag->count() > 0;
    options.report_path = report_path;
    noise::NoiseFlags flags;
    flags.model = model;
    flags.tau = tau;
    flags.seed = seed;
    flags.sigma = sigma;
    if (pos_flag->count() > 0) flags.sigma_pos = sigma_pos;
    if (alt_flag->count() > 0) flags.sigma_alt = sigma_alt;
    flags.sigma_rot = sigma_rot;
    if (time_flag->count() > 0) flags.sigma_time = sigma_time;
    if (fov_flag->count() > 0) flags.sigma_fov = sigma_fov;
    flags.biases = biases;
    options.spec = noise::NoiseSpecFromFlags(flags);
    const noise::PerturbResult result = noise::PerturbCollection(options);
    if (!common.quiet) std::cout << noise::DescribePerturbResult(result, options.spec);
    return 0;
  });
}

}  // namespace lsds
