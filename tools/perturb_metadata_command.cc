// lsds perturb-metadata COLLECTION --sigma POS_M[,ROT_DEG] --seed N [-o FILE]
// [--model M] [...]
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "libs/noise/perturb_collection.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tools/command.h"

namespace lsds {

namespace {

using noise::Field;

std::vector<double> ParseNumbers(const std::string& text, const std::string& flag) {
  std::vector<double> numbers;
  for (const std::string& part : Split(text, ',')) {
    const char* begin = part.c_str();
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(begin, &end);
    if (part.empty() || end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
      throw Error(flag + ": '" + part + "' is not a number (in '" + text + "')");
    }
    numbers.push_back(value);
  }
  return numbers;
}

// Sets fields [first, first + count) from `text`: one value for all of them or
// one per field.
void SetFields(std::array<double, noise::kFieldCount>* values,
               int first,
               int count,
               const std::string& text,
               const std::string& flag) {
  const std::vector<double> numbers = ParseNumbers(text, flag);
  if (numbers.size() != 1 && static_cast<int>(numbers.size()) != count) {
    throw Error(flag + ": expected 1" + (count > 1 ? " or " + std::to_string(count) : "") +
                " value(s), got " + std::to_string(numbers.size()) + " in '" + text + "'");
  }
  for (int i = 0; i < count; ++i)
    (*values)[first + i] = numbers.size() == 1 ? numbers[0] : numbers[i];
}

// --bias FIELD=VALUE[,VALUE...]
void ParseBias(const std::string& text, std::array<double, noise::kFieldCount>* bias) {
  struct Target {
    const char* name;
    int first;
    int count;
  };
  static const Target targets[] = {{"pos", noise::kEast, 2},
                                   {"alt", noise::kUp, 1},
                                   {"rot", noise::kRoll, 3},
                                   {"time", noise::kTime, 1},
                                   {"fov", noise::kHfov, 1},
                                   {"east", noise::kEast, 1},
                                   {"north", noise::kNorth, 1},
                                   {"up", noise::kUp, 1},
                                   {"roll", noise::kRoll, 1},
                                   {"pitch", noise::kPitch, 1},
                                   {"yaw", noise::kYaw, 1}};
  const size_t equals = text.find('=');
  std::vector<std::string> names;
  for (const Target& target : targets) names.push_back(target.name);
  if (equals == std::string::npos) {
    throw Error("--bias: expected FIELD=VALUE (FIELD one of " + Join(names, ", ") + "), got '" +
                text + "'");
  }
  const std::string name = text.substr(0, equals);
  for (const Target& target : targets) {
    if (name == target.name) {
      SetFields(bias, target.first, target.count, text.substr(equals + 1), "--bias " + name);
      return;
    }
  }
  throw Error("--bias: unknown field '" + name + "'" + DidYouMean(name, names) +
              "; expected one of " + Join(names, ", "));
}

}  // namespace

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
    noise::NoiseSpec& spec = options.spec;
    spec.model = noise::ParseNoiseModel(model);
    spec.tau = tau;
    spec.seed = seed;
    bool any_noise = !biases.empty();
    if (!sigma.empty()) {
      const std::vector<double> values = ParseNumbers(sigma, "--sigma");
      if (values.size() > 2) throw Error("--sigma: expected POS_M[,ROT_DEG], got '" + sigma + "'");
      spec.sigma[noise::kEast] = spec.sigma[noise::kNorth] = spec.sigma[noise::kUp] = values[0];
      if (values.size() == 2) {
        spec.sigma[noise::kRoll] = spec.sigma[noise::kPitch] = spec.sigma[noise::kYaw] = values[1];
      }
      any_noise = true;
    }
    if (pos_flag->count() > 0) spec.sigma[noise::kEast] = spec.sigma[noise::kNorth] = sigma_pos;
    if (alt_flag->count() > 0) spec.sigma[noise::kUp] = sigma_alt;
    if (!sigma_rot.empty()) SetFields(&spec.sigma, noise::kRoll, 3, sigma_rot, "--sigma-rot");
    if (time_flag->count() > 0) spec.sigma[noise::kTime] = sigma_time;
    if (fov_flag->count() > 0) spec.sigma[noise::kHfov] = sigma_fov;
    any_noise = any_noise || pos_flag->count() > 0 || alt_flag->count() > 0 || !sigma_rot.empty() ||
                time_flag->count() > 0 || fov_flag->count() > 0;
    for (const std::string& bias : biases) ParseBias(bias, &spec.bias);
    if (!any_noise) {
      throw Error(
          "no noise given: pass --sigma POS_M[,ROT_DEG], a --sigma-* flag or "
          "--bias");
    }
    const noise::PerturbResult result = noise::PerturbCollection(options);
    const nlohmann::json& position = result.summary["position_m"];
    const nlohmann::json& rotation = result.summary["rotation_deg"];
    std::cout << "wrote " << result.output.string() << ": " << result.frames << " frames, "
              << spec.Describe() << "\n"
              << "  position error rms " << position["rms"].get<double>() << " m (max "
              << position["max_abs"].get<double>() << "), rotation error rms "
              << rotation["rms"].get<double>() << " deg (max " << rotation["max_abs"].get<double>()
              << ")\n";
    if (result.registered_as.empty()) {
      std::cout << "  not registered in collection.json: the output is outside "
                   "the collection\n";
    } else {
      std::cout << "  registered in collection.json as metadata variant '" << result.registered_as
                << "'\n";
    }
    if (result.report_summary) {
      const nlohmann::json& r = *result.report_summary;
      std::cout << "report " << result.report->string() << ": " << r["corners"].get<int64_t>()
                << " target corners in " << r["frames_with_targets"].get<int64_t>()
                << " frames moved mean " << r["mean_px"].get<double>() << " px, p95 "
                << r["p95_px"].get<double>() << " px, max " << r["max_px"].get<double>() << " px\n";
    }
    return 0;
  });
}

}  // namespace lsds
