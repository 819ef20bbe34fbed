#include "generator/lang/scene/position.h"

#include <cmath>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "generator/lang/vocabulary.h"
#include "generator/plan/relations.h"
#include "generator/plan/terrain_height.h"
#include "libs/geometry/geodesy.h"

namespace lsds {

bool IsRelationKey(const std::string& canonical_key) {
  return canonical_key == "near" || canonical_key == "behind" || canonical_key == "infrontof";
}

namespace {

// VISIBLE FROM: an eye and the object seen from (which never blocks its own view).
struct Sight {
  Eigen::Vector3d eye;
  const Placed* viewer = nullptr;
  std::string what;
};

// What the constraints of a position node leave: the space the centre is drawn in, what the
// object stands on, and the conditions a draw must meet.
struct Constraints {
  AxisBox space;
  bool on = false, in = false;  // stands on `surface` / lies within another object's box
  StandingSurface surface;
  std::set<std::string> supports;
  std::vector<std::pair<Relation, std::string>> relations;  // and their text, for messages
  std::optional<Eigen::Vector3d> facing;                    // the point the object turns to
  std::vector<Sight> sights;
};

// The references of AROUND and the relations: one name, or {name: margin or distance, ...}.
std::vector<std::pair<std::string, Node>> References(const Node& c) {
  if (c->is_object()) return c.Members();
  return {{ReadString(c), Node{}}};
}

// Reads a position node's constraints in the order written, shrinking the space by each.
class ConstraintReader {
 public:
  ConstraintReader(const PlacementContext& context, const Definition& def, int64_t copy)
      : context_(context), def_(def), copy_(copy) {}

  Constraints Read(const Node& pos) {
    if (pos)
      for (const auto& [key, c] : pos.Members()) {
        const std::string k = CanonicalKey(key);
        if (k == "on") On(c);
        if (k == "in") In(c);
        if (k == "around") Around(c);
        if (IsRelationKey(k)) Relations(key, k, c);
        if (k == "visiblefrom") VisibleFrom(key, c);
        if (k == "facing") Facing(c);
        if (k == "within") Within(c);
        if (k == "wgs84") Wgs84(c);
      }
    if (!out_.on && !out_.in &&
        out_.space.lo.z() <= -kHuge) {  // no vertical constraint: the ground
      out_.surface = TerrainSurface(context_.terrain);
      Shrink(out_.surface.footprint, pos ? pos : def_.body, "ON:terrain (implied)");
      out_.on = true;
      if (!context_.terrain_symbol.empty()) out_.supports.insert(context_.terrain_symbol);
    }
    return std::move(out_);
  }

 private:
  void Shrink(const AxisBox& box, const Node& constraint, const std::string& what) {
    out_.space.Intersect(box);
    if (out_.space.Empty())
      constraint.Fail(def_.symbol + " copy " + std::to_string(copy_ + 1) +
                      ": the position space is empty after " + what + " (it leaves " +
                      out_.space.ToString() + ")");
  }

  const Placed& AnyCopy(const Node& where, const std::string& symbol) {
    return context_.placed.AnyCopy(where, symbol, context_.rng);
  }

  void On(const Node& c) {
    const std::string ref = ReadString(c);
    out_.surface = ref == context_.terrain_symbol ? TerrainSurface(context_.terrain)
                                                  : SurfaceOf(AnyCopy(c, ref));
    Shrink(out_.surface.footprint, c, "ON:" + ref);
    out_.on = true;
    out_.supports.insert(ref);
  }

  void In(const Node& c) {
    const std::string ref = ReadString(c);
    const Placed* x = ref == context_.terrain_symbol ? nullptr : &AnyCopy(c, ref);
    if (!x || (!x->object.visible && x->has_support)) {
      // IN the terrain, or IN a zone (an invisible object standing on something), is standing on
      // that ground: within the zone's footprint, its base on the ground.
      out_.surface = x ? SurfaceOf(*x) : TerrainSurface(context_.terrain);
      Shrink(out_.surface.footprint, c, "IN:" + ref);
      out_.on = true;
    } else {
      Shrink(x->aabb, c, "IN:" + ref);
      out_.in = true;
    }
    out_.supports.insert(ref);
  }

  // AROUND restricts x and y (by 10 m, or the margin given); z comes from ON/IN or the ground.
  void Around(const Node& c) {
    for (const auto& [ref, margin_node] : References(c)) {
      Eigen::Vector3d margin(10, 10, 0);
      if (margin_node) {
        if (margin_node->is_array()) {
          margin = SampleVec3(margin_node, context_.rng);
        } else {
          const double m = SampleScalar(margin_node, context_.rng);
          margin = Eigen::Vector3d(m, m, 0);
        }
        if (margin.minCoeff() < 0) margin_node.Fail("AROUND margin must be >= 0");
      }
      AxisBox box = AnyCopy(c, ref).aabb;
      box.lo -= margin;
      box.hi += margin;
      box.lo.z() = -kHuge;
      box.hi.z() = kHuge;
      Shrink(box, c, "AROUND:" + ref);
    }
  }

  void Relations(const std::string& key, const std::string& k, const Node& c) {
    for (const auto& [ref, distance_node] : References(c)) {
      Relation r;
      r.kind = k == "near"     ? Relation::Kind::kNear
               : k == "behind" ? Relation::Kind::kBehind
                               : Relation::Kind::kInFront;
      if (k == "near") r.distance = 10;  // default: within 10 m, as AROUND
      if (distance_node) {
        r.distance = SampleScalar(distance_node, context_.rng);
        if (!(r.distance >= 0)) distance_node.Fail(key + " distance must be >= 0 (m)");
      }
      const PlannedObject& x = AnyCopy(c, ref).object;
      r.ref_xy = x.position.head<2>();
      r.ref_heading = HeadingOf(x.world_from_object);
      AxisBox box;
      Eigen::Vector2d lo, hi;
      RelationBounds(r, &lo, &hi);
      box.lo.head<2>() = lo.cwiseMax(box.lo.head<2>());
      box.hi.head<2>() = hi.cwiseMin(box.hi.head<2>());
      const std::string what = key + ":" + ref;
      Shrink(box, c, what);
      out_.relations.push_back({r, what});
    }
  }

  void VisibleFrom(const std::string& key, const Node& c) {
    Sight sight;
    if (c->is_array()) {
      for (size_t i = 0; i < 3; ++i) sight.eye[i] = ReadNumber(c.Item(i));
      sight.what = key + ":" + c->dump();
    } else {
      sight.viewer = &AnyCopy(c, ReadString(c));
      sight.eye = sight.viewer->object.position;
      sight.what = key + ":" + ReadString(c);
    }
    out_.sights.push_back(sight);
  }

  void Facing(const Node& c) {
    if (c->is_array()) {
      Eigen::Vector3d point = Eigen::Vector3d::Zero();
      for (size_t i = 0; i < c->size(); ++i) point[i] = ReadNumber(c.Item(i));
      out_.facing = point;
    } else {
      out_.facing = AnyCopy(c, ReadString(c)).object.position;
    }
  }

  void Within(const Node& c) {
    if (!c->is_array() || c->size() != 2) c.Fail("within is [[x0,y0,z0],[x1,y1,z1]]");
    AxisBox box;
    for (int i = 0; i < 3; ++i) {
      box.lo[i] = ReadNumber(c.Item(0).Item(i));
      box.hi[i] = ReadNumber(c.Item(1).Item(i));
    }
    Shrink(box, c, "within");
  }

  // WGS84: the ENU point of [latitude, longitude] pins x and y.
  void Wgs84(const Node& c) {
    if (!context_.geo)
      c.Fail("a WGS84 position needs a georeferenced scene: add georeference{latitude, longitude}");
    if (!c->is_array() || c->size() != 2) c.Fail("wgs84 is [latitude, longitude] (degrees)");
    const double latitude = ReadNumber(c.Item(0)), longitude = ReadNumber(c.Item(1));
    if (!(std::abs(latitude) <= 90) || !(std::abs(longitude) <= 180))
      c.Fail("wgs84 is [latitude, longitude] within [-90, 90] and [-180, 180] degrees");
    const Eigen::Vector3d at =
        EnuOf(*context_.geo, Geodetic{latitude, longitude, context_.geo->altitude_m});
    AxisBox box;
    box.lo.head<2>() = at.head<2>();
    box.hi.head<2>() = at.head<2>();
    Shrink(box, c, "wgs84");
  }

  const PlacementContext& context_;
  const Definition& def_;
  int64_t copy_;
  Constraints out_;
};

// Records in the planned object what its placement was (the plan's placement record).
void RecordPlacement(const Constraints& cs, const OverlapRules& rules, Placed* p) {
  PlannedObject& o = p->object;
  p->has_support = cs.on;
  p->support = cs.surface;
  o.placement_lo = cs.space.lo;
  o.placement_hi = cs.space.hi;
  o.on_overlap = rules.on_overlap;
  o.retries = rules.retries;
  o.relations = cs.relations;
  o.facing = cs.facing;
  o.sights.clear();
  for (const Sight& sight : cs.sights)
    o.sights.push_back(
        {sight.eye, sight.viewer ? sight.viewer->object.name : std::string(), sight.what});
}

// One draw of the centre in the space (the base on the surface when the object stands ON
// something), then the turn to what it faces.
void DrawCentre(const PlacementContext& context,
                const Constraints& cs,
                const Node& where,
                const std::string& symbol,
                const Eigen::Matrix3d& unturned,
                PlannedObject* o) {
  o->world_from_object = unturned;
  // FACING turns the object after its centre is drawn; it is drawn with the half-width no turn
  // exceeds, so the turned box stays in the space.
  Eigen::Vector3d half = o->world_from_object.cwiseAbs() * (0.5 * o->extent);
  if (cs.facing) half.head<2>().setConstant(HorizontalRadius(o->world_from_object, o->extent));
  for (int i = 0; i < 3; ++i) {
    if (i == 2 && cs.on) continue;
    const double lo = cs.space.lo[i] + half[i], hi = cs.space.hi[i] - half[i];
    if (std::abs(cs.space.lo[i]) >= kHuge || std::abs(cs.space.hi[i]) >= kHuge)
      where.Fail(symbol + ": the position space is unbounded along " + "xyz"[i] +
                 "; add ON, IN or within");
    o->position[i] =
        lo <= hi ? context.rng.Uniform(lo, hi) : 0.5 * (cs.space.lo[i] + cs.space.hi[i]);
  }
  if (cs.on) {
    const double ground = cs.surface.terrain
                              ? TerrainHeight(context.terrain, o->position.x(), o->position.y())
                              : cs.surface.top;
    o->position.z() = ground + half.z();
  }
  // A turn about the vertical keeps the box's height, so the base stays.
  if (cs.facing) o->world_from_object = FacingRotation(unturned, o->position, *cs.facing);
}

// The relation (or, with `sights`, the line of sight) a drawn centre breaks, the last one listed
// when several, or null.
const std::string* Broken(const PlacementContext& context,
                          const Constraints& cs,
                          const PlannedObject& o,
                          bool sights) {
  const std::string* broken = nullptr;
  if (!sights) {
    for (const auto& [relation, what] : cs.relations)
      if (!RelationHolds(relation, o.position)) broken = &what;
    return broken;
  }
  for (const Sight& sight : cs.sights)
    if (context.placed.Blocked(sight.eye, o.position, sight.viewer)) broken = &sight.what;
  return broken;
}

}  // namespace

bool PlaceObject(const PlacementContext& context,
                 const Definition& def,
                 const Node& pos,
                 int64_t copy,
                 int64_t count,
                 const OverlapRules& rules,
                 Placed* p) {
  const Node& where = pos ? pos : def.body;
  const Constraints cs = ConstraintReader(context, def, copy).Read(pos);
  RecordPlacement(cs, rules, p);
  PlannedObject& o = p->object;
  const bool may_overlap = rules.overlap || rules.on_overlap == "allow";
  const Eigen::Matrix3d unturned = o.world_from_object;
  const std::string* broken = nullptr;  // the relation or sight the last draw broke
  for (int attempt = 0;; ++attempt) {
    DrawCentre(context, cs, where, def.symbol, unturned, &o);
    broken = Broken(context, cs, o, /*sights=*/false);
    if (!broken) {
      p->aabb = AabbOf(o.position, o.world_from_object, o.extent);
      o.support = !cs.on               ? PlannedObject::Support::kNone
                  : cs.surface.terrain ? PlannedObject::Support::kTerrain
                                       : PlannedObject::Support::kTop;
      o.support_top = cs.surface.top;
      o.supports.assign(cs.supports.begin(), cs.supports.end());
      o.overlap_allowed = may_overlap;
      broken = Broken(context, cs, o, /*sights=*/true);
      if (!broken && (may_overlap || !context.placed.Collides(*p, o.supports))) return true;
    }
    if (attempt >= rules.retries) break;
  }
  const std::string tried =
      " after " + std::to_string(rules.retries) + " retries in " + cs.space.ToString();
  const std::string which = def.symbol + ": cannot place copy " + std::to_string(copy + 1) +
                            " of " + std::to_string(count);
  if (rules.on_overlap == "delete") return false;
  if (broken)
    where.Fail(which + " satisfying " + *broken + tried +
               "; widen the relation or the space, or raise retries");
  if (rules.on_overlap == "hide") {
    o.visible = false;
    o.target = false;
    return true;
  }
  where.Fail(which + " without overlap" + tried +
             "; enlarge the space, lower the count, set overlap:true or on_overlap:delete");
}

}  // namespace lsds
