#include "generator/lang/capture/camera_paths.h"

#include <algorithm>
#include <cmath>

#include "generator/lang/capture/quota_draws.h"
#include "generator/lang/distributions.h"
#include "generator/lang/vocabulary.h"
#include "generator/plan/terrain_height.h"
#include "libs/geometry/attitude.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A path's scalar that sets a frame quantity (a random pose's altitude above the terrain or
// off-nadir angle), drawn within the frame's bin when a quota asks for importance sampling of it.
double SampleWithinBin(const Node& n,
                       const std::string& quantity,
                       const FrameDemand* demand,
                       Rng& rng) {
  if (const auto bin = DemandedBin(demand, quantity))
    if (const auto v = SampleScalarWithin(n, bin->first, bin->second, rng)) return *v;
  return SampleScalar(n, rng);
}

}  // namespace

std::string PathKind(const std::string& key) {
  const std::string k = CanonicalKey(key);
  return k == "incrementpoint" ? "incrementpoints" : k;
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> SpaceOf(const Node& g) {
  const Node space = g.Find("space");
  if (!space || !space->is_array() || space->size() != 2 || !space->at(0).is_array() ||
      space->at(0).size() != 3 || !space->at(1).is_array() || space->at(1).size() != 3)
    (space ? space : g).Fail("create path needs a space [[x0,y0,z0],[x1,y1,z1]]");
  Eigen::Vector3d lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = ReadNumber(space.Item(0).Item(static_cast<size_t>(a)));
    hi[a] = ReadNumber(space.Item(1).Item(static_cast<size_t>(a)));
    if (lo[a] > hi[a]) space.Fail("a space is [[x0,y0,z0],[x1,y1,z1]] with each lo <= hi");
  }
  return {lo, hi};
}

std::array<std::vector<double>, 3> GridAxes(const Node& g) {
  std::array<std::vector<double>, 3> axes;
  if (g.Find("x") || g.Find("y")) {
    if (!g.Find("x") || !g.Find("y") || !g.Find("altitude"))
      g.Fail("a grid needs x, y and altitude ranges [start, stop, count]");
    axes[0] = ExpandRange(g.Find("x"));
    axes[1] = ExpandRange(g.Find("y"));
    axes[2] = ExpandRange(g.Find("altitude"));
    return axes;
  }
  const Node start = g.Find("start"), step = g.Find("step"), count = g.Find("count");
  if (!start || !step || !count)
    g.Fail("increment points need start [x,y,z], step [dx,dy,dz] and count [nx,ny,nz]");
  Rng dummy(0);
  const Eigen::Vector3d s = SampleVec3(start, dummy), d = SampleVec3(step, dummy),
                        n = SampleVec3(count, dummy);
  for (int i = 0; i < 3; ++i) {
    if (n[i] < 1 || n[i] > 100000 || n[i] != std::floor(n[i]))
      count.Fail("counts must be whole numbers >= 1");
    for (int j = 0; j < static_cast<int>(n[i]); ++j) axes[i].push_back(s[i] + j * d[i]);
  }
  return axes;
}

int64_t CameraPaths::FrameCount(const Definition& path, uint64_t segment) {
  const auto [kind, g] = path.body.Members().front();
  if (PathKind(kind) == "waypoints" && g->is_object()) return FlightOf(g, segment).frame_count;
  Rng count_rng = Rng::For(seed_, StreamTag::kCount, segment);
  return FrameCount(path, count_rng);
}

int64_t CameraPaths::FrameCount(const Definition& path, Rng& count_rng) {
  const auto [kind, g] = path.body.Members().front();
  const std::string k = PathKind(kind);
  if (k == "createhemi" || k == "hemi") {
    lsds::CheckKeys(g, KindVocabulary("create_hemi"), "create hemi");
    for (const char* key : {"camradius", "objangle", "camangle"})
      if (!g.Find(key))
        g.Fail("create hemi needs cam_radius, obj_angle and cam_angle ([start, stop, count])");
    return static_cast<int64_t>(ExpandRange(g.Find("camradius")).size() *
                                ExpandRange(g.Find("objangle")).size() *
                                ExpandRange(g.Find("camangle")).size());
  }
  if (k == "grid" || k == "incrementpoints") {
    lsds::CheckKeys(g, KindVocabulary("grid"), "grid");
    PointBlueprint(g);
    const auto axes = GridAxes(g);
    return static_cast<int64_t>(axes[0].size() * axes[1].size() * axes[2].size());
  }
  if (k == "random" || k == "randomposes") {
    lsds::CheckKeys(g, KindVocabulary("random"), "random poses");
    if (!g.Find("count")) g.Fail("random poses need a count");
    return SampleCount(g.Find("count"), count_rng);
  }
  if (k == "waypoints") {
    if (!g->is_array() || g->empty()) g.Fail("waypoints are a non-empty list");
    return static_cast<int64_t>(g->size());
  }
  if (k == "createpath") {
    lsds::CheckKeys(g, KindVocabulary("create_path"), "create path");
    SpaceOf(g);
    if (!g.Find("points")) g.Fail("create path needs points (how many) and a space");
    return SampleCount(g.Find("points"), count_rng);
  }
  lsds::CheckKeys(g, KindVocabulary("create_point"), "create point");
  if (!g.Find("position")) g.Fail("create point needs a position");
  if (const Node c = g.Find("count")) return SampleCount(c, count_rng);
  return 1;
}

// A smooth flight (docs/languages.md, "Smooth flights"): `waypoints:{points: [...], speed: m/s,
// interpolation: linear | spline}` is flown at `speed`, one frame every speed / fps metres along
// the polyline or a Catmull-Rom spline through the waypoints; the attitude is interpolated (slerp)
// between the waypoints' attitudes. Waypoint intervals are drawn once per path instance.
const Flight& CameraPaths::FlightOf(const Node& g, uint64_t segment) {
  const auto cached = flights_.find(segment);
  if (cached != flights_.end()) return cached->second;
  Rng rng = Rng::For(seed_, StreamTag::kFlight, segment);
  Flight flight;
  const bool spline = ReadFlightSettings(g, setup_.fps, rng, &flight);
  const Node points = g.Find("points");
  std::vector<Rigid3d> poses;
  for (size_t j = 0; j < points->size(); ++j)
    poses.push_back(WaypointPose(points.Item(j), rng, {}));  // before any frame: as planned
  flight.Build(poses, spline);
  const double frames = std::floor(flight.length / flight.spacing + 1e-9) + 1;
  if (frames > 1e6)
    g.Fail("the flight has " + FormatNumber(frames) + " frames; lower the fps or raise the speed");
  flight.frame_count = static_cast<int64_t>(frames);
  return flights_.emplace(segment, std::move(flight)).first->second;
}

Rigid3d CameraPaths::Pose(const Definition& path,
                          int64_t i,
                          Rng& rng,
                          uint64_t segment,
                          std::optional<Eigen::Vector3d>* velocity,
                          const FrameDemand* demand,
                          const std::vector<ObjectChange>& moved) {
  const auto [kind, g] = path.body.Members().front();
  const std::string k = PathKind(kind);
  if (k == "createhemi" || k == "hemi") return HemiPose(g, i, rng, moved);
  if (k == "grid" || k == "incrementpoints") return GridPose(g, i, rng);
  if (k == "random" || k == "randomposes") return RandomPose(g, rng, demand);
  if (k == "waypoints" && g->is_object()) {
    const Flight& flight = FlightOf(g, segment);
    const FlightSample at = flight.At(static_cast<double>(i) * flight.spacing);
    if (velocity) *velocity = at.velocity;
    return at.cam_from_world;
  }
  if (k == "waypoints") return WaypointPose(g.Item(static_cast<size_t>(i)), rng, moved);
  if (k == "createpath") return SpacePose(g, rng);
  return PointPose(g, rng, moved);
}

ObjectTrack CameraPaths::Track(const Definition& path, Rng& rng) {
  ObjectTrack track;
  const int64_t n = FrameCount(path, rng);
  std::vector<Eigen::Vector3d> centres;
  for (int64_t i = 0; i < n; ++i)
    centres.push_back(CameraCenterInWorld(Pose(path, i, rng, 0, nullptr, nullptr)));
  const auto [kind, g] = path.body.Members().front();
  const std::string k = PathKind(kind);
  if (k != "createhemi" && k != "hemi") {
    track.knots = centres;
    track.arcs.assign(centres.empty() ? 0 : centres.size() - 1, std::nullopt);
    return track;
  }
  // A hemi's ring (one radius and elevation) is a circle about the vertical through the centre:
  // from one azimuth to the next the object follows the arc, and a ring over a full turn
  // (`obj angle:[0,360,n]`) is closed by the arc back to its first point. From one ring to the
  // next it goes straight.
  const Node azimuth = g.Find("objangle");
  const auto az = ExpandRange(azimuth), el = ExpandRange(g.Find("camangle")),
             radii = ExpandRange(g.Find("camradius"));
  const double turn =
      azimuth->is_array() ? ReadNumber(azimuth.Item(1)) - ReadNumber(azimuth.Item(0)) : 0.0;
  const bool closed = az.size() > 1 && std::abs(std::abs(turn) - 360.0) < 1e-9;
  for (size_t i = 0; i < centres.size(); ++i) {
    const size_t a = i % az.size();
    const double e = el[(i / az.size()) % el.size()] * kDeg;
    ObjectTrack::Arc arc;
    arc.radius = radii[i / (az.size() * el.size())] * std::cos(e);
    arc.from_deg = az[a];
    // The ring's centre: the hemi centre raised by r sin e, found from the point itself.
    arc.centre = centres[i] - arc.radius * Eigen::Vector3d(std::cos(arc.from_deg * kDeg),
                                                           std::sin(arc.from_deg * kDeg),
                                                           0);
    track.knots.push_back(centres[i]);
    if (a + 1 < az.size()) {
      arc.to_deg = az[a + 1];
      track.arcs.push_back(arc);
      continue;
    }
    if (closed) {
      arc.to_deg = az[0] + turn;
      track.arcs.push_back(arc);
      track.knots.push_back(centres[i - a]);
    }
    if (i + 1 < centres.size()) track.arcs.push_back(std::nullopt);
  }
  return track;
}

// Radius, then elevation, then azimuth vary slowest to fastest; the camera looks at the centre
// (the `center` key, else the camera's first target, else the origin).
Rigid3d CameraPaths::HemiPose(const Node& g,
                              int64_t i,
                              Rng& rng,
                              const std::vector<ObjectChange>& moved) const {
  const auto radii = ExpandRange(g.Find("camradius")), az = ExpandRange(g.Find("objangle")),
             el = ExpandRange(g.Find("camangle"));
  const size_t a = static_cast<size_t>(i) % az.size();
  const size_t e = (static_cast<size_t>(i) / az.size()) % el.size();
  const size_t r = static_cast<size_t>(i) / (az.size() * el.size());
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  const Node c = FindKey(g, KindVocabulary("create_hemi"), "center");
  if (c)
    center = Point(c, rng, moved);
  else if (!first_target_.empty())
    center = ObjectCenter(setup_.camera->body, first_target_, moved);
  const Eigen::Vector3d eye =
      center + radii[r] * Eigen::Vector3d(std::cos(el[e] * kDeg) * std::cos(az[a] * kDeg),
                                          std::cos(el[e] * kDeg) * std::sin(az[a] * kDeg),
                                          std::sin(el[e] * kDeg));
  return LookAt(eye, center);
}

Rigid3d CameraPaths::GridPose(const Node& g, int64_t i, Rng& rng) const {
  const auto axes = GridAxes(g);
  const size_t nx = axes[0].size(), ny = axes[1].size();
  const size_t z = static_cast<size_t>(i) / (nx * ny);
  const size_t y = (static_cast<size_t>(i) / nx) % ny;
  size_t x = static_cast<size_t>(i) % nx;
  if (y % 2 == 1) x = nx - 1 - x;  // serpentine (lawnmower) order
  Eigen::Vector3d p(axes[0][x], axes[1][y], axes[2][z]);
  if (const Node n = g.Find("perturb")) {
    const Eigen::Vector3d amp = SampleVec3(n, rng);
    for (int j = 0; j < 3; ++j) p[j] += rng.Uniform(-amp[j], amp[j]);
  }
  if (const Node point = PointBlueprint(g)) {
    // The paper's point blueprint (section 3.2): its position box is the noise about each grid
    // point, its rotation (or look_at) the attitude there.
    p += SampleVec3(point.Find("position"), rng);
    p.z() += TerrainHeight(plan_.terrain, p.x(), p.y());
    if (const Node l = point.Find("lookat")) return LookAt(p, Point(l, rng, {}));
    Attitude att{0, -90, 0};
    if (const Node r = FindKey(point, KindVocabulary("create_point"), "rotation")) {
      const Eigen::Vector3d rpy = SampleVec3(r, rng);
      att = Attitude{rpy.x(), rpy.y(), rpy.z()};
    }
    return CamFromEnu(p, att);
  }
  p.z() += TerrainHeight(plan_.terrain, p.x(), p.y());
  Attitude att{0, -90, 0};
  if (const Node n = g.Find("roll")) att.roll_deg = SampleScalar(n, rng);
  if (const Node n = g.Find("pitch")) att.pitch_deg = SampleScalar(n, rng);
  if (const Node n = g.Find("yaw")) att.yaw_deg = SampleScalar(n, rng);
  return CamFromEnu(p, att);
}

Node CameraPaths::PointBlueprint(const Node& g) const {
  const Node ref = FindKey(g, KindVocabulary("grid"), "point");
  if (!ref) return Node{};
  Node point = ref;
  if (ref->is_string()) {
    const std::string symbol = ReadString(ref);
    const Definition* path = capture_ ? capture_->Find(symbol) : nullptr;
    if (!path || path->kind != "path" || path->body->size() != 1 ||
        PathKind(path->body.Members().front().first) != "createpoint")
      ref.Fail("'" + symbol +
               "' is not a create point path: the point blueprint is "
               "N = path{create point:{position:[[x0,y0,z0],[x1,y1,z1]], rotation:[...]}}");
    point = path->body.Members().front().second;
  }
  if (!point->is_object())
    ref.Fail("a point blueprint is a create point block {position, rotation} or its path symbol");
  lsds::CheckKeys(point, KindVocabulary("create_point"), "point blueprint");
  if (!point.Find("position"))
    point.Fail("a point blueprint needs a position: the box of noise about each grid point");
  if (const Node c = point.Find("count")) c.Fail("the grid sets how many points; drop count");
  if (const Node n = g.Find("perturb"))
    n.Fail("the point blueprint's position box is the perturbation; give one of them");
  for (const char* key : {"roll", "pitch", "yaw"})
    if (const Node n = g.Find(key))
      n.Fail("the point blueprint sets the attitude; drop " + std::string(key));
  return point;
}

Rigid3d CameraPaths::RandomPose(const Node& g, Rng& rng, const FrameDemand* demand) const {
  const Eigen::Vector2d half =
      plan_.terrain.present ? Eigen::Vector2d(0.5 * plan_.terrain.size) : Eigen::Vector2d(50, 50);
  Eigen::Vector3d p(rng.Uniform(-half.x(), half.x()), rng.Uniform(-half.y(), half.y()), 50);
  if (const Node n = g.Find("x")) p.x() = SampleScalar(n, rng);
  if (const Node n = g.Find("y")) p.y() = SampleScalar(n, rng);
  if (const Node n = g.Find("altitude")) p.z() = SampleWithinBin(n, "altitude", demand, rng);
  p.z() += TerrainHeight(plan_.terrain, p.x(), p.y());
  double off_nadir = 0, yaw = rng.Uniform(0, 360);
  if (const Node n = g.Find("offnadir")) off_nadir = SampleWithinBin(n, "off_nadir", demand, rng);
  if (const Node n = g.Find("yaw")) yaw = SampleScalar(n, rng);
  if (const Node n = g.Find("offnadir"))
    CheckRange(n, KindVocabulary("random").Key("off_nadir"), off_nadir);
  return CamFromEnu(p, Attitude{0, -90 + off_nadir, yaw});
}

int64_t CameraPaths::ShotStart(const Definition& path, int64_t first, int64_t i) const {
  const auto [kind, g] = path.body.Members().front();
  const std::string k = PathKind(kind);
  if (k == "waypoints") return first;
  if (k == "grid" || k == "incrementpoints") {
    const auto axes = GridAxes(g);
    const int64_t level = static_cast<int64_t>(axes[0].size() * axes[1].size());
    return first + (i / level) * level;
  }
  return first + i;
}

Eigen::Vector3d CameraPaths::RigCameraVelocity(const Definition& path,
                                               uint64_t segment,
                                               int64_t i,
                                               const Rigid3d& cam_from_rig) {
  const auto [kind, g] = path.body.Members().front();
  const Flight& flight = FlightOf(g, segment);
  const double s = static_cast<double>(i) * flight.spacing;
  const double h = std::min(0.01, 0.5 * flight.length);
  const double lo = std::max(0.0, s - h), hi = std::min(flight.length, s + h);
  if (!(hi > lo)) return Eigen::Vector3d::Zero();
  auto centre = [&](double at) {
    return CameraCenterInWorld(cam_from_rig * flight.At(at).cam_from_world);
  };
  return (centre(hi) - centre(lo)) * (flight.speed / (hi - lo));
}

// One waypoint: [x,y,z] (nadir), [x,y,z,roll,pitch,yaw] or {position, attitude | look_at}.
Rigid3d CameraPaths::WaypointPose(const Node& w,
                                  Rng& rng,
                                  const std::vector<ObjectChange>& moved) const {
  if (w->is_array()) {
    if (w->size() != 3 && w->size() != 6)
      w.Fail("a waypoint is [x,y,z] (nadir) or [x,y,z,roll,pitch,yaw]");
    std::vector<double> v;
    for (size_t j = 0; j < w->size(); ++j) v.push_back(SampleScalar(w.Item(j), rng));
    const Attitude att = v.size() == 6 ? Attitude{v[3], v[4], v[5]} : Attitude{0, -90, 0};
    return CamFromEnu(Datum({v[0], v[1], v[2]}), att);
  }
  lsds::CheckKeys(w, KindVocabulary("waypoint"), "waypoint");
  return PointPose(w, rng, moved);
}

// A waypoint or point position in the world frame: with camera settings `heights:agl`, its z is
// above the terrain under it.
Eigen::Vector3d CameraPaths::Datum(Eigen::Vector3d p) const {
  if (setup_.heights_agl) p.z() += TerrainHeight(plan_.terrain, p.x(), p.y());
  return p;
}

// {position, rotation|attitude: [roll,pitch,yaw] | look_at: [x,y,z] or an object}
Rigid3d CameraPaths::PointPose(const Node& g,
                               Rng& rng,
                               const std::vector<ObjectChange>& moved) const {
  const Node pos = g.Find("position");
  if (!pos) g.Fail("expected a position");
  const Eigen::Vector3d p = Datum(SampleVec3(pos, rng));
  if (const Node l = g.Find("lookat")) return LookAt(p, Point(l, rng, moved));
  Attitude att{0, -90, 0};
  if (const Node r = FindKey(g, KindVocabulary("create_point"), "rotation")) {
    const Eigen::Vector3d rpy = SampleVec3(r, rng);
    att = Attitude{rpy.x(), rpy.y(), rpy.z()};
  }
  return CamFromEnu(p, att);
}

// Create Path: a point drawn uniformly in the space, looking down (or by `rotation`).
Rigid3d CameraPaths::SpacePose(const Node& g, Rng& rng) const {
  const auto [lo, hi] = SpaceOf(g);
  Eigen::Vector3d p;
  for (int a = 0; a < 3; ++a) p[a] = rng.Uniform(lo[a], hi[a]);
  Attitude att{0, -90, 0};
  if (const Node r = FindKey(g, KindVocabulary("create_path"), "rotation")) {
    const Eigen::Vector3d rpy = SampleVec3(r, rng);
    att = Attitude{rpy.x(), rpy.y(), rpy.z()};
  }
  return CamFromEnu(Datum(p), att);
}

Eigen::Vector3d CameraPaths::Point(const Node& n,
                                   Rng& rng,
                                   const std::vector<ObjectChange>& moved) const {
  if (n->is_string()) return ObjectCenter(n, ReadString(n), moved);
  return SampleVec3(n, rng);
}

Eigen::Vector3d CameraPaths::ObjectCenter(const Node& where,
                                          const std::string& symbol,
                                          const std::vector<ObjectChange>& moved) const {
  for (const PlannedObject& o : plan_.objects) {
    if (o.symbol != symbol) continue;
    Eigen::Vector3d centre = o.position;
    for (const ObjectChange& c : moved)  // the frame's changes in order: the last place counts
      if (c.object == o.name && c.position) centre = *c.position;
    return centre;
  }
  where.Fail("'" + symbol + "' is not a placed object of the scene");
}

}  // namespace lsds
