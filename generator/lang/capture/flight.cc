#include "generator/lang/capture/flight.h"

#include <algorithm>

#include "generator/lang/vocabulary.h"

namespace lsds {

void Flight::Build(const std::vector<Rigid3d>& poses, bool spline) {
  std::vector<Eigen::Vector3d> centres;
  std::vector<Eigen::Quaterniond> rotations;
  for (const Rigid3d& p : poses) {
    centres.push_back(CameraCenterInWorld(p));
    rotations.push_back(p.rotation);
  }
  Build(centres, rotations, spline);
}

void Flight::Build(const std::vector<Eigen::Vector3d>& centres,
                   const std::vector<Eigen::Quaterniond>& rotations,
                   bool spline) {
  attitudes = rotations;
  const size_t n = centres.size();
  auto at = [&](size_t i, double t) -> Eigen::Vector3d {
    const Eigen::Vector3d& p1 = centres[i];
    const Eigen::Vector3d& p2 = centres[i + 1];
    if (!spline) return p1 + t * (p2 - p1);
    // Catmull-Rom (uniform), the end points repeated.
    const Eigen::Vector3d& p0 = centres[i == 0 ? 0 : i - 1];
    const Eigen::Vector3d& p3 = centres[std::min(i + 2, n - 1)];
    const double t2 = t * t, t3 = t2 * t;
    return 0.5 * ((2 * p1) + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t2 +
                  (-p0 + 3 * p1 - 3 * p2 + p3) * t3);
  };
  for (size_t i = 0; i + 1 < n; ++i) {
    for (int k = (i == 0 ? 0 : 1); k <= kSamplesPerSegment; ++k) {
      const double t = static_cast<double>(k) / kSamplesPerSegment;
      const Eigen::Vector3d p = at(i, t);
      along.push_back(points.empty() ? 0.0 : along.back() + (p - points.back()).norm());
      points.push_back(p);
      param.push_back(static_cast<double>(i) + t);
    }
  }
  length = along.back();
}

FlightSample Flight::At(double s) const {
  s = std::clamp(s, 0.0, length);
  const size_t j =
      static_cast<size_t>(std::upper_bound(along.begin(), along.end(), s) - along.begin());
  const size_t hi = std::clamp<size_t>(j, 1, along.size() - 1), lo = hi - 1;
  const double span = along[hi] - along[lo];
  const double t = span > 0 ? (s - along[lo]) / span : 0.0;
  const Eigen::Vector3d centre = points[lo] + t * (points[hi] - points[lo]);
  const double u = param[lo] + t * (param[hi] - param[lo]);
  const size_t w = std::min(static_cast<size_t>(u), attitudes.size() - 2);
  const Eigen::Quaterniond rotation =
      attitudes[w].slerp(u - static_cast<double>(w), attitudes[w + 1]);
  FlightSample sample;
  sample.cam_from_world.rotation = rotation;
  sample.cam_from_world.translation = -(rotation * centre);
  sample.centre = centre;
  const Eigen::Vector3d d = points[hi] - points[lo];
  sample.tangent = d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::Zero();
  sample.velocity = speed * sample.tangent;
  return sample;
}

bool ReadFlightSettings(const Node& g, double fps, Rng& rng, Flight* flight) {
  lsds::CheckKeys(g, KindVocabulary("flight"), "waypoints");
  const Node points = g.Find("points"), speed = g.Find("speed");
  if (!points || !points->is_array() || points->size() < 2)
    (points ? points : g).Fail("a flight needs points: at least two waypoints");
  if (!speed) g.Fail("a flight needs a speed (m/s)");
  flight->speed = SampleInRange(speed, KindVocabulary("flight").Key("speed"), rng);
  flight->spacing = flight->speed / fps;
  if (const Node n = g.Find("interpolation")) {
    const std::string v = ReadString(n);
    if (v != "linear" && v != "spline")
      n.Fail("interpolation is linear or spline, not '" + v + "'");
    return v == "spline";
  }
  return false;
}

}  // namespace lsds
