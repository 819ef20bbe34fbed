// The noise flags of `lsds perturb-metadata` (docs/perturb-metadata.md) as
// the user gave them, turned into a NoiseSpec, and the lines the command
// prints about a run.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "perturb/noise_spec.h"
#include "perturb/perturb_collection.h"

namespace lsds::noise {

struct NoiseFlags {
  std::string model = "gaussian";  // gaussian | uniform | gauss-markov
  double tau = 0;                  // gauss-markov correlation time, s
  uint64_t seed = 0;
  std::string sigma;  // --sigma POS_M[,ROT_DEG]; empty: not given
  // The --sigma-* flags, each overriding --sigma for its fields.
  std::optional<double> sigma_pos;   // east and north, m
  std::optional<double> sigma_alt;   // up, m
  std::string sigma_rot;             // S (every axis) or ROLL,PITCH,YAW, deg
  std::optional<double> sigma_time;  // s
  std::optional<double> sigma_fov;   // horizontal field of view, deg
  std::vector<std::string> biases;   // --bias FIELD=VALUE[,VALUE...], repeatable
};

// The noise the flags describe. Throws lsds::Error naming the flag for a value
// that is not a number, a wrong count of values, an unknown --bias field (with
// a suggestion), or no noise at all.
NoiseSpec NoiseSpecFromFlags(const NoiseFlags& flags);

// What `lsds perturb-metadata` prints after a run: the output, the noise, the
// realized errors, where the variant is registered, and the report's summary.
std::string DescribePerturbResult(const PerturbResult& result, const NoiseSpec& spec);

}  // namespace lsds::noise
