// The objects an LSCENE program has placed so far, in the order placed, and the questions
// Algorithm 1 asks of them: a copy of a symbol, the surface an object stands on, whether a new
// object overlaps one, whether a line of sight is blocked.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "generator/lang/random.h"
#include "generator/lang/scene/placement_grid.h"
#include "generator/lang/values.h"
#include "generator/plan/plan.h"
#include "libs/geometry/oriented_box.h"

namespace lsds {

// Algorithm 1 starts from the "max sized 3D bounding box": this many metres each way.
constexpr double kHuge = 1e7;

// An axis-aligned box, world frame, metres; a position space or an object's bounds.
struct AxisBox {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(-kHuge);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(kHuge);
  bool EmptyXY() const { return lo.x() > hi.x() || lo.y() > hi.y(); }
  bool Empty() const { return EmptyXY() || lo.z() > hi.z(); }
  void Intersect(const AxisBox& o) {
    lo = lo.cwiseMax(o.lo);
    hi = hi.cwiseMin(o.hi);
  }
  std::string ToString() const;  // [x0,x1]x[y0,y1]x[z0,z1], "inf" past kHuge
};

// Where an object stands: a footprint (x and y only) and either the terrain surface or a flat top.
struct StandingSurface {
  AxisBox footprint;
  bool terrain = false;
  double top = 0;
};

struct Placed {
  PlannedObject object;
  AxisBox aabb;
  StandingSurface support;  // what it stands on (ON), when it has an ON constraint
  bool has_support = false;
};

AxisBox AabbOf(const Eigen::Vector3d& center,
               const Eigen::Matrix3d& rotation,
               const Eigen::Vector3d& extent);
OrientedBox ObbOf(const PlannedObject& o);

// The ground without an object: the terrain's extent, or a 100 m x 100 m plane at z = 0.
StandingSurface TerrainSurface(const PlannedTerrain& terrain);

// The surface an object ON `x` stands on: x's top within x's footprint. An invisible x standing on
// something (a placement zone) passes on what it stands on, within its own footprint.
StandingSurface SurfaceOf(const Placed& x);

class PlacedObjects {
 public:
  // Adds a placed copy of its symbol; a visible one joins the overlap grid.
  void Add(const Placed& p);
  const std::vector<Placed>& all() const { return placed_; }

  // The first placed copy of `symbol`; an error at `where` when it has none (count 0, deleted).
  const Placed& FirstCopy(const Node& where, const std::string& symbol) const;
  // A copy of `symbol` drawn uniformly with `rng`; an error at `where` when it has none.
  const Placed& AnyCopy(const Node& where, const std::string& symbol, Rng& rng) const;

  // VISIBLE FROM: whether a visible object placed so far (other than the viewer) stands between
  // the eye and the centre.
  bool Blocked(const Eigen::Vector3d& eye,
               const Eigen::Vector3d& centre,
               const Placed* viewer) const;

  // Whether visible `p` overlaps (or comes within the larger of the two separations of) a visible
  // object placed before it, other than its supports.
  bool Collides(const Placed& p, const std::vector<std::string>& supports) const;

 private:
  // A footprint on the ground grown by a separation, for the placement grid.
  static PlacementGrid::Rect FootprintOf(const AxisBox& aabb, double separation);

  std::vector<Placed> placed_;
  // The placement grid's cell, metres: about the size of the clutter it is for (bushes, rocks,
  // vehicles); a building spans a few cells, anything over 64 cells goes on the grid's short list.
  PlacementGrid grid_{4.0};             // the visible ones among placed_, by ground cell
  mutable std::vector<uint32_t> near_;  // Collides' scratch list
  std::map<std::string, std::vector<size_t>> by_symbol_;
};

}  // namespace lsds
