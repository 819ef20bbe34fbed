// What to perturb and how: the noise model, its per-field sigmas and biases,
// tau and the seed. Units: metres for position, degrees for attitude and field
// of view, seconds for time.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "libs/geometry/world_frame.h"
#include "perturb/noise_process.h"

namespace lsds::noise {

// The perturbed fields, each drawn from its own stream of random numbers.
// Position noise is drawn along east/north/up (metres) and mapped into the
// declared world frame; attitude noise is a small rotation vector about the
// heading-level axes forward/right/down (roll/pitch/yaw, degrees).
enum Field : int { kEast, kNorth, kUp, kRoll, kPitch, kYaw, kTime, kHfov, kFieldCount };

// "east_m", "north_m", "up_m", "roll_deg", "pitch_deg", "yaw_deg", "time_s",
// "hfov_deg".
const char* FieldName(int field);

struct NoiseSpec {
  NoiseModel model = NoiseModel::kGaussian;
  double tau = 0;  // seconds; gauss-markov only
  uint64_t seed = 0;
  std::array<double, kFieldCount> sigma{};  // standard deviation per field
  std::array<double, kFieldCount> bias{};   // constant offset per field, added to the noise

  // Throws lsds::Error naming the flag: negative or non-finite sigma,
  // non-finite bias, missing or non-positive tau for gauss-markov, tau given
  // for another model.
  void Validate() const;
  bool IsZero() const;  // no sigma and no bias: the output equals the truth

  // The "parameters" object of the metadata's noise record.
  nlohmann::json ParametersJson(const WorldFrame& world) const;
  // One line for collection.json's variant description.
  std::string Describe() const;
};

}  // namespace lsds::noise
