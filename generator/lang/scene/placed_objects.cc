#include "generator/lang/scene/placed_objects.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "generator/plan/relations.h"

namespace lsds {

std::string AxisBox::ToString() const {
  auto f = [](double v) {
    if (std::abs(v) >= kHuge) return std::string(v < 0 ? "-inf" : "inf");
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return std::string(buf);
  };
  return "[" + f(lo.x()) + "," + f(hi.x()) + "]x[" + f(lo.y()) + "," + f(hi.y()) + "]x[" +
         f(lo.z()) + "," + f(hi.z()) + "]";
}

AxisBox AabbOf(const Eigen::Vector3d& center,
               const Eigen::Matrix3d& rotation,
               const Eigen::Vector3d& extent) {
  const Eigen::Vector3d half = rotation.cwiseAbs() * (0.5 * extent);
  AxisBox b;
  b.lo = center - half;
  b.hi = center + half;
  return b;
}

OrientedBox ObbOf(const PlannedObject& o) {
  OrientedBox b;
  b.center = o.position;
  b.half_extents = 0.5 * o.extent;
  b.world_from_box = o.world_from_object;
  return b;
}

StandingSurface TerrainSurface(const PlannedTerrain& terrain) {
  StandingSurface s;
  if (terrain.present) {
    s.footprint.lo.head<2>() = -0.5 * terrain.size;
    s.footprint.hi.head<2>() = 0.5 * terrain.size;
    s.terrain = true;
  } else {  // no terrain: a 100 m x 100 m ground plane at z = 0
    s.footprint.lo.head<2>() = Eigen::Vector2d(-50, -50);
    s.footprint.hi.head<2>() = Eigen::Vector2d(50, 50);
  }
  return s;
}

StandingSurface SurfaceOf(const Placed& x) {
  StandingSurface s;
  s.footprint = x.aabb;
  if (!x.object.visible && x.has_support) {
    s.footprint.Intersect(x.support.footprint);
    s.terrain = x.support.terrain;
    s.top = x.support.top;
  } else {
    s.top = x.aabb.hi.z();
  }
  s.footprint.lo.z() = -kHuge;
  s.footprint.hi.z() = kHuge;
  return s;
}

void PlacedObjects::Add(const Placed& p) {
  by_symbol_[p.object.symbol].push_back(placed_.size());
  if (p.object.visible)
    grid_.Insert(static_cast<uint32_t>(placed_.size()), FootprintOf(p.aabb, p.object.separation));
  placed_.push_back(p);
}

const Placed& PlacedObjects::FirstCopy(const Node& where, const std::string& symbol) const {
  auto it = by_symbol_.find(symbol);
  if (it == by_symbol_.end() || it->second.empty())
    where.Fail("'" + symbol + "' has no placed copies to refer to (count 0 or all deleted)");
  return placed_[it->second.front()];
}

const Placed& PlacedObjects::AnyCopy(const Node& where, const std::string& symbol, Rng& rng) const {
  auto it = by_symbol_.find(symbol);
  if (it == by_symbol_.end() || it->second.empty())
    where.Fail("'" + symbol + "' has no placed copies to refer to (count 0 or all deleted)");
  return placed_[it->second[static_cast<size_t>(
      rng.UniformInt(0, static_cast<int64_t>(it->second.size()) - 1))]];
}

bool PlacedObjects::Blocked(const Eigen::Vector3d& eye,
                            const Eigen::Vector3d& centre,
                            const Placed* viewer) const {
  for (const Placed& q : placed_)
    if (q.object.visible && &q != viewer && SegmentCrossesBox(ObbOf(q.object), eye, centre))
      return true;
  return false;
}

PlacementGrid::Rect PlacedObjects::FootprintOf(const AxisBox& aabb, double separation) {
  return {aabb.lo.x() - separation,
          aabb.lo.y() - separation,
          aabb.hi.x() + separation,
          aabb.hi.y() + separation};
}

// Each footprint is in the grid grown by its own separation and the query by p's, so the pairs
// within the larger of the two gaps are among the neighbours the grid returns.
bool PlacedObjects::Collides(const Placed& p, const std::vector<std::string>& supports) const {
  if (!p.object.visible) return false;
  grid_.Near(FootprintOf(p.aabb, p.object.separation), &near_);
  for (const uint32_t index : near_) {
    const Placed& q = placed_[index];
    if (!q.object.visible ||
        std::find(supports.begin(), supports.end(), q.object.symbol) != supports.end())
      continue;
    // The larger separation of the two: the gap either asks for.
    const double gap = std::max(p.object.separation, q.object.separation);
    if (q.aabb.hi.x() + gap <= p.aabb.lo.x() || p.aabb.hi.x() + gap <= q.aabb.lo.x() ||
        q.aabb.hi.y() + gap <= p.aabb.lo.y() || p.aabb.hi.y() + gap <= q.aabb.lo.y() ||
        q.aabb.hi.z() + gap <= p.aabb.lo.z() || p.aabb.hi.z() + gap <= q.aabb.lo.z())
      continue;
    OrientedBox mine = ObbOf(p.object);
    mine.half_extents.array() += gap;
    if (mine.Intersects(ObbOf(q.object))) return true;
  }
  return false;
}

}  // namespace lsds
