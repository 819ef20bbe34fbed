#include "generator/lang/capture/object_track.h"

#include <algorithm>
#include <cmath>

namespace lsds {
namespace {

constexpr double kDeg = M_PI / 180.0;

}  // namespace

void ObjectTrack::TimePerFrame(double fps) {
  times.clear();
  for (size_t j = 0; j < knots.size(); ++j) times.push_back(static_cast<double>(j) / fps);
}

void ObjectTrack::TimeAtSpeed(double speed) {
  times.assign(knots.empty() ? 0 : 1, 0.0);
  for (size_t j = 0; j + 1 < knots.size(); ++j)
    times.push_back(times.back() + SegmentLength(j) / speed);
}

double ObjectTrack::SegmentLength(size_t j) const {
  if (const std::optional<Arc>& arc = arcs[j])
    return arc->radius * std::abs(arc->to_deg - arc->from_deg) * kDeg;
  return (knots[j + 1] - knots[j]).norm();
}

FlightSample ObjectTrack::At(double t) const {
  FlightSample sample;
  if (knots.empty()) return sample;
  sample.centre = knots.back();
  if (knots.size() == 1) return sample;
  t = std::clamp(t, 0.0, Duration());
  // The segment holding t (the next one at a knot; a segment of no duration is passed over).
  size_t j =
      static_cast<size_t>(std::upper_bound(times.begin(), times.end(), t + 1e-9) - times.begin());
  j = std::clamp<size_t>(j, 1, knots.size() - 1) - 1;
  const double span = times[j + 1] - times[j];
  // A time within rounding of a knot's is the knot: frame j of the leg is exactly knot j.
  double u = span > 0 ? (t - times[j]) / span : 1.0;
  if (std::abs(u) < 1e-9) u = 0;
  if (std::abs(u - 1) < 1e-9) u = 1;
  if (const std::optional<Arc>& arc = arcs[j]) {
    const double a = (arc->from_deg + u * (arc->to_deg - arc->from_deg)) * kDeg;
    sample.centre = arc->centre + arc->radius * Eigen::Vector3d(std::cos(a), std::sin(a), 0);
    if (span > 0) {
      const double rate = (arc->to_deg - arc->from_deg) * kDeg / span;  // rad/s
      sample.velocity = arc->radius * rate * Eigen::Vector3d(-std::sin(a), std::cos(a), 0);
    }
  } else {
    const Eigen::Vector3d d = knots[j + 1] - knots[j];
    sample.centre = knots[j] + u * d;
    if (span > 0) sample.velocity = d / span;
  }
  if (u == 0) sample.centre = knots[j];
  if (u == 1) sample.centre = knots[j + 1];
  const double speed = sample.velocity.norm();
  if (speed > 0) sample.tangent = sample.velocity / speed;
  return sample;
}

}  // namespace lsds
