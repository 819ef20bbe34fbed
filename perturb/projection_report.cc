#include "perturb/projection_report.h"

#include <algorithm>
#include <cmath>

namespace lsds::noise {

namespace {
constexpr double kHistogramMin = 1e-9;
constexpr double kHistogramMax = 1e9;
constexpr double kBinRatio = 1.002;
}  // namespace

nlohmann::json FrameDisplacement::ToJson() const {
  return {{"index", index},
          {"targets", targets},
          {"corners", corners},
          {"mean_px", mean_px},
          {"p95_px", p95_px},
          {"max_px", max_px}};
}

FrameDisplacement MeasureDisplacement(const Frame& frame,
                                      const WorldFrame& world,
                                      const MetadataFrame& measured,
                                      double near) {
  FrameDisplacement result;
  result.index = frame.index;
  const Rigid3d true_cam_from_enu = world.CamFromEnuMetres(frame.camera.cam_from_world_rotation,
                                                           frame.camera.cam_from_world_translation);
  const Rigid3d measured_cam_from_enu =
      CamFromEnu(world.EnuMetresFromWorld(measured.position), measured.attitude);
  const PinholeCamera& true_camera = frame.camera.intrinsics;
  const PinholeCamera& measured_camera = measured.camera;
  for (const ObjectTruth& object : frame.objects) {
    if (!(object.in_frame > 0) || !object.obb) continue;  // no 3D box: no corners to project
    ++result.targets;
    for (const Eigen::Vector3d& corner_in_world : object.obb->Corners()) {
      const Eigen::Vector3d corner_in_enu = world.EnuMetresFromWorld(corner_in_world);
      const Eigen::Vector3d in_true_cam = true_cam_from_enu * corner_in_enu;
      const Eigen::Vector3d in_measured_cam = measured_cam_from_enu * corner_in_enu;
      if (!(in_true_cam.z() > near) || !(in_measured_cam.z() > near)) continue;
      const double distance =
          (measured_camera.ImageFromCam(in_measured_cam) - true_camera.ImageFromCam(in_true_cam))
              .norm();
      result.displacements_px.push_back(distance);
    }
  }
  result.corners = static_cast<int>(result.displacements_px.size());
  if (result.corners > 0) {
    double sum = 0;
    for (double d : result.displacements_px) {
      sum += d;
      result.max_px = std::max(result.max_px, d);
    }
    result.mean_px = sum / result.corners;
    result.p95_px = Quantile(result.displacements_px, 0.95);
  }
  return result;
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double position = q * static_cast<double>(values.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(position));
  const size_t above = std::min(below + 1, values.size() - 1);
  const double t = position - static_cast<double>(below);
  return values[below] + t * (values[above] - values[below]);
}

QuantileHistogram::QuantileHistogram() {
  const size_t bins =
      static_cast<size_t>(std::ceil(std::log(kHistogramMax / kHistogramMin) / std::log(kBinRatio)));
  bins_.assign(bins + 2, 0);  // + underflow (bin 0) and overflow (last)
}

void QuantileHistogram::Add(double value) {
  if (!std::isfinite(value)) value = kHistogramMax * 2;
  size_t bin = 0;
  if (value >= kHistogramMin) {
    const double position = std::log(value / kHistogramMin) / std::log(kBinRatio);
    bin = std::min(bins_.size() - 1, static_cast<size_t>(position) + 1);
  }
  ++bins_[bin];
  if (count_ == 0) {
    min_ = max_ = value;
  } else {
    min_ = std::min(min_, value);
    max_ = std::max(max_, value);
  }
  ++count_;
}

double QuantileHistogram::Quantile(double q) const {
  if (count_ == 0) return 0.0;
  // Nearest rank: the smallest value with at least q * count values at or below
  // it.
  const int64_t rank = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(q * count_)));
  int64_t seen = 0;
  for (size_t bin = 0; bin < bins_.size(); ++bin) {
    seen += bins_[bin];
    if (seen < rank) continue;
    if (bin == 0) return std::max(0.0, std::min(min_, kHistogramMin));
    // Geometric centre of the bin, kept inside the observed range.
    const double centre = kHistogramMin * std::pow(kBinRatio, static_cast<double>(bin) - 0.5);
    return std::min(max_, std::max(min_, centre));
  }
  return max_;
}

void DisplacementSummary::Add(const FrameDisplacement& frame) {
  ++frames_;
  if (frame.targets > 0) ++frames_with_targets_;
  targets_ += frame.targets;
  for (double d : frame.displacements_px) {
    sum_ += d;
    max_ = std::max(max_, d);
    histogram_.Add(d);
  }
}

nlohmann::json DisplacementSummary::ToJson() const {
  return {{"frames", frames_},
          {"frames_with_targets", frames_with_targets_},
          {"targets", targets_},
          {"corners", corners()},
          {"mean_px", mean_px()},
          {"p95_px", p95_px()},
          {"max_px", max_px()}};
}

}  // namespace lsds::noise
