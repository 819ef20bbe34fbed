// An object moving along a path that is not a smooth flight (docs/languages.md, "Objects that
// move"): the path's points in the order the camera would fly them (a waypoint list, a grid's
// lawnmower rows, a hemi's rings, create point / create path / random draws). The object is at
// point j on the leg's frame j, as the camera would be, or, with a speed, it goes from point to
// point at that speed. Between two points it moves in a straight line, except along a hemi ring
// where it follows the circle (an orbit): positions, velocities and headings are closed-form.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "generator/lang/capture/flight.h"

namespace lsds {

struct ObjectTrack {
  // A circular arc from knot j to knot j + 1: the point at azimuth a (degrees) is
  // `centre + radius (cos a, sin a, 0)`; the azimuth goes linearly from `from_deg` to `to_deg`.
  struct Arc {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius = 0;
    double from_deg = 0;
    double to_deg = 0;
  };

  std::vector<Eigen::Vector3d> knots;    // the path's points in order
  std::vector<std::optional<Arc>> arcs;  // per segment (knots.size() - 1): an arc or a line
  std::vector<double> times;             // seconds from the first knot to each knot

  // Knot j at j / fps (the camera's timing: one point per frame).
  void TimePerFrame(double fps);
  // Every segment at `speed` m/s along its line or arc.
  void TimeAtSpeed(double speed);
  // The length of segment j: its chord, or its arc.
  double SegmentLength(size_t j) const;
  // Seconds from the first knot to the last.
  double Duration() const { return times.empty() ? 0.0 : times.back(); }
  // The point `t` seconds after the first knot (clamped to the track): knot j exactly at
  // times[j]; the velocity and tangent are the segment's (the next one's at a knot, the last
  // one's at the end).
  FlightSample At(double t) const;
};

}  // namespace lsds
