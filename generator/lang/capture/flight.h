// A smooth flight (docs/languages.md, "Smooth flights"): a curve through waypoints, sampled densely
// so that arc length maps to a point, the attitude is interpolated between the waypoints' and the
// velocity follows the speed. Camera paths and moving objects share it.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "generator/lang/random.h"
#include "generator/lang/values.h"
#include "libs/geometry/rigid3.h"

namespace lsds {

// One point of a flight.
struct FlightSample {
  Rigid3d cam_from_world;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();    // the point on the curve
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // world m/s
  Eigen::Vector3d tangent = Eigen::Vector3d::Zero();   // unit direction of travel
};

struct Flight {
  double speed = 0;    // m/s
  double spacing = 0;  // metres between frames: speed / fps
  double length = 0;   // of the curve, metres
  int64_t frame_count = 0;
  std::vector<Eigen::Quaterniond> attitudes;  // cam_from_world at waypoints
  std::vector<Eigen::Vector3d> points;        // dense curve
  std::vector<double> along;                  // arc length at each point
  std::vector<double> param;                  // waypoint parameter (i + t)

  static constexpr int kSamplesPerSegment = 64;

  // The curve through the centres of `poses`, with their attitudes.
  void Build(const std::vector<Rigid3d>& poses, bool spline);
  // The curve through `centres` (an object's path has identity attitudes): the polyline, or a
  // uniform Catmull-Rom spline with the end points repeated.
  void Build(const std::vector<Eigen::Vector3d>& centres,
             const std::vector<Eigen::Quaterniond>& rotations,
             bool spline);
  // The sample `s` metres along the curve (clamped to [0, length]).
  FlightSample At(double s) const;
};

// The keys every flight shares (points, speed, interpolation), checked; fills the speed and the
// spacing of frames at `fps` and returns whether it is a spline. The speed is drawn from `rng`.
bool ReadFlightSettings(const Node& g, double fps, Rng& rng, Flight* flight);

}  // namespace lsds
