// What metadata noise does to the data: how far the corners of the targets' 3D
// OBBs move in the image when they are projected with the measured (perturbed)
// camera instead of the true one.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/collection/model.h"

namespace lsds::noise {

struct FrameDisplacement {
  int64_t index = 0;
  int targets = 0;                             // objects with in_frame > 0
  int corners = 0;                             // their OBB corners in front of both cameras
  double mean_px = 0, p95_px = 0, max_px = 0;  // 0 when no corner counts
  std::vector<double> displacements_px;        // one per counted corner
  nlohmann::json ToJson() const;               // without the per-corner list
};

// Projects every corner of every target of `frame` (in_frame > 0) with the true
// camera of the frame and with the camera that `measured` states (position,
// attitude, intrinsics), and measures the distance between the two image
// points. Corners closer than `near` metres to either camera's image plane (or
// behind it) are not counted.
FrameDisplacement MeasureDisplacement(const Frame& frame,
                                      const WorldFrame& world,
                                      const MetadataFrame& measured,
                                      double near = 1e-3);

// Linear-interpolated quantile of a small list (q in [0, 1]); 0 for an empty
// list.
double Quantile(std::vector<double> values, double q);

// Streaming quantiles in constant memory: log-spaced bins of relative width 0.2
// %, so quantiles are exact to 0.2 % (values below 1e-9 count as 0).
class QuantileHistogram {
 public:
  QuantileHistogram();
  void Add(double value);
  int64_t count() const { return count_; }
  double Quantile(double q) const;

 private:
  std::vector<int64_t> bins_;
  int64_t count_ = 0;
  double min_ = 0, max_ = 0;
};

// The summary over all frames: mean, p95 and max over all counted corners.
class DisplacementSummary {
 public:
  void Add(const FrameDisplacement& frame);
  nlohmann::json ToJson() const;
  int64_t corners() const { return histogram_.count(); }
  double mean_px() const { return corners() > 0 ? sum_ / static_cast<double>(corners()) : 0.0; }
  double p95_px() const { return histogram_.Quantile(0.95); }
  double max_px() const { return max_; }

 private:
  int64_t frames_ = 0, frames_with_targets_ = 0, targets_ = 0;
  double sum_ = 0, max_ = 0;
  QuantileHistogram histogram_;
};

}  // namespace lsds::noise
