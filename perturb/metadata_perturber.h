// Perturbs metadata frames: draws the realized error of each field and applies
// it to the truth.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "libs/collection/model.h"
#include "perturb/noise_process.h"
#include "perturb/noise_spec.h"

namespace lsds::noise {

// The error of one frame: bias + noise per field (NoiseSpec units).
struct RealizedError {
  std::array<double, kFieldCount> value{};

  Eigen::Vector3d position_enu_m() const { return {value[kEast], value[kNorth], value[kUp]}; }
  // Rotation vector about the heading-level axes forward/right/down, degrees.
  Eigen::Vector3d rotation_vector_deg() const { return {value[kRoll], value[kPitch], value[kYaw]}; }
  double rotation_angle_deg() const { return rotation_vector_deg().norm(); }
};

// The measured attitude: the true one turned by `rotation_vector_deg`
// (heading-level axes forward, right, down, i.e. north/east/down turned by the
// true yaw). The angle between the true and the measured attitude is exactly
// the norm of the vector. A zero vector returns `truth` unchanged.
Attitude RotateAttitude(const Attitude& truth, const Eigen::Vector3d& rotation_vector_deg);

// Frames must be visited in time order (file order) because gauss-markov noise
// carries state; the draws themselves depend only on (seed, field, frame
// index).
class MetadataPerturber {
 public:
  MetadataPerturber(const NoiseSpec& spec, const WorldFrame& world);

  RealizedError NextError(int64_t frame_index, double time);
  // `truth` with `error` applied and recorded in its "error" member. Fields
  // with zero error keep their true values bit for bit.
  MetadataFrame Apply(const MetadataFrame& truth, const RealizedError& error) const;
  MetadataFrame Perturb(const MetadataFrame& truth) {
    return Apply(truth, NextError(truth.index, truth.time));
  }

 private:
  NoiseSpec spec_;
  WorldFrame world_;
  std::vector<ScalarProcess> processes_;
};

// Running statistics of realized errors (constant memory), for the metadata's
// "summary".
class ErrorStatistics {
 public:
  void Add(const RealizedError& error);
  int64_t count() const { return count_; }
  nlohmann::json ToJson() const;

 private:
  struct Running {
    int64_t n = 0;
    double mean = 0, m2 = 0, sum_squares = 0, max_abs = 0;
    void Add(double x);
    nlohmann::json ToJson() const;
  };
  int64_t count_ = 0;
  std::array<Running, kFieldCount> fields_;
  Running position_, horizontal_, rotation_;
};

}  // namespace lsds::noise
