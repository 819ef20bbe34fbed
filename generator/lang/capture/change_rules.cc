#include "generator/lang/capture/change_rules.h"

#include "generator/lang/capture/object_changes.h"
#include "generator/lang/environment.h"
#include "generator/lang/scene/ground.h"
#include "generator/lang/vocabulary.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

class RuleReader {
 public:
  RuleReader(const Program& capture,
             const Timeline& timeline,
             const ChangeTargets& targets,
             const CameraSetup& setup,
             CameraPaths* paths,
             uint64_t seed,
             ClassSwaps* swaps,
             Plan* plan)
      : capture_(capture),
        timeline_(timeline),
        targets_(targets),
        setup_(setup),
        paths_(paths),
        seed_(seed),
        swaps_(swaps),
        plan_(plan) {}

  // One collection entry `key: value`: a scene change set applied with the entry's timing, or
  // the changes of one object or environment symbol.
  void ReadEntry(const std::string& key, const Node& value) {
    const Definition* set = capture_.Find(key);
    for (const Node& block : Blocks(value)) {
      if (!block->is_object()) block.Fail("expected {when:{...}, change...} for " + key);
      if (set && set->kind == "scene_change") {  // SCS1:{after:P1:1} applies the set then
        block.CheckKeys(TimingKeys(), "scene change set entry " + key);
        for (const auto& [object, changes] : set->body.Members())
          for (const Node& change : Blocks(changes))
            Add(object, change, block, "scene change set " + key);
      } else if (set) {
        block.Fail("'" + key + "' is a " + set->kind +
                   "; a collection entry names the camera, an object or a scene change set");
      } else {
        Add(key, block, block, "scene change of " + key);
      }
    }
  }

  std::vector<Rule> rules;

 private:
  void Add(const std::string& object,
           const Node& block,
           const Node& timing_block,
           const std::string& where) {
    const auto environment = targets_.environment_symbols.find(object);
    if (environment != targets_.environment_symbols.end())
      AddEnvironment(object, environment->second, block, timing_block, where);
    else
      AddObject(object, block, timing_block, where);
  }

  // Any LSCENE function of the sky, light, atmosphere, skylight or terrain material, as in the
  // scene (docs/languages.md).
  void AddEnvironment(const std::string& symbol,
                      const std::string& kind,
                      const Node& block,
                      const Node& timing_block,
                      const std::string& where) {
    std::vector<std::string> keys = EnvironmentKeys(kind, true);
    const std::vector<std::string> timing = TimingKeys();
    keys.insert(keys.end(), timing.begin(), timing.end());
    block.CheckKeys(keys, where);
    Rule rule = NewRule(symbol, block, timing_block);
    rule.environment_kind = kind;
    if (kind == "terrain" && HasTerrainShape(block)) {
      rule.terrain_shape = true;
      CheckShotBoundaries(rule, symbol, timing_block);
    }
    Rng probe(0);  // bad values are reported now, not on some frame
    PlannedEnvironment scratch = EnvironmentOf(*plan_);
    ApplyEnvironment(rule.environment_kind, block, probe, &scratch);
    for (std::string& w : ImplausibleLight(rule.environment_kind, block, scratch))
      plan_->warnings.push_back(std::move(w));
    if (scratch.sun.clock_utc_s && !plan_->geo)
      block.Fail(
          "a sun given by date and time needs a place: add a georeference{latitude, longitude, "
          "altitude} to the scene");
    rules.push_back(std::move(rule));
  }

  void AddObject(const std::string& object,
                 const Node& block,
                 const Node& timing_block,
                 const std::string& where) {
    std::vector<std::string> keys = KindVocabulary("object_change").Spellings();
    const std::vector<std::string> timing = TimingKeys();
    keys.insert(keys.end(), timing.begin(), timing.end());
    block.CheckKeys(keys, where);
    if (!HasObject(*plan_, targets_, object)) {
      const std::vector<std::string> names(targets_.scene_objects.begin(),
                                           targets_.scene_objects.end());
      block.Fail("'" + object + "' is not an object of the scene" + DidYouMean(object, names));
    }
    Rule rule = NewRule(object, block, timing_block);
    ReadMotion(block, &rule);
    if (const Node cls = block.Find("class")) {
      if (!cls->is_string() && !cls->is_object())
        cls.Fail("class must be a name or a choice {name: weight}");
      swaps_->Declare(object, cls);
    }
    // Sample once with a throwaway stream so that bad values are reported now, not on some frame.
    Rng probe(0);
    for (const PlannedObject& o : plan_->objects)
      if (o.symbol == object) {
        DrawObjectChange(rule, o, probe, nullptr, swaps_);
        break;
      }
    rules.push_back(std::move(rule));
  }

  // A terrain shape change starts (and ends) where a shot starts: motion and its truth are
  // measured between frames of one shot over a still world, so the ground may change only
  // between shots (docs/languages.md, "Terrain shape changes").
  void CheckShotBoundaries(const Rule& rule,
                           const std::string& symbol,
                           const Node& timing_block) const {
    for (const int64_t step : {rule.when.begin, rule.when.end}) {
      if (step <= 0 || step >= timeline_.steps()) continue;
      const Segment& seg = timeline_.At(step);
      const int64_t shot = paths_->ShotStart(*seg.path, seg.first, step - seg.first);
      if (shot == step) continue;
      timing_block.Fail(
          "a terrain shape change takes effect only where a shot starts (motion is measured "
          "within a shot over a still ground); this one " +
          std::string(step == rule.when.begin ? "starts" : "ends") + " at frame " +
          std::to_string(step) + ", inside the shot of " + seg.path->symbol + "(" +
          std::to_string(seg.repetition) + ") that starts at frame " + std::to_string(shot) +
          "; time it by a path instance: " + symbol + ":{during:" + seg.path->symbol + ":" +
          std::to_string(seg.repetition) + ", height:{...}} or " + symbol +
          ":{after:" + seg.path->symbol + ":" + std::to_string(seg.repetition) + ", height:{...}}");
    }
  }

  Rule NewRule(const std::string& symbol, const Node& block, const Node& timing_block) const {
    Rule rule;
    rule.object_symbol = symbol;
    rule.block = block;
    rule.id = rules.size() + 1;
    ReadTiming(timing_block, timeline_, &rule.when);
    return rule;
  }

  // `move:[P2, P3:2]`, `speed` and `heading` of an object's change block; `rescatter` is checked
  // here too (it draws a new position, a move follows a path).
  void ReadMotion(const Node& block, Rule* rule) const {
    const Node move = block.Find("move");
    if (const Node n = block.Find("speed"); n && !move)
      n.Fail("speed times an object's move; add move:[P]");
    if (const Node h = block.Find("heading")) {
      if (!move) h.Fail("heading turns an object along its move; add move:[P]");
      if (!h->is_boolean()) h.Fail("heading is true or false");
      rule->heading = h->get<bool>();
    }
    if (const Node r = block.Find("rescatter")) {
      if (!r->is_boolean()) r.Fail("rescatter is true or false");
      if (move) r.Fail("an object either moves along a path or is re-scattered");
      if (const Node p = block.Find("position"))
        p.Fail("an object is either placed at a position or re-scattered, not both");
    }
    if (!move) return;
    for (const char* key : {"offset", "position"})
      if (const Node n = block.Find(key))
        n.Fail("a moving object's position comes from its path; set it in another block");
    const std::vector<Node> items = Blocks(move);
    if (items.empty()) move.Fail("move lists paths: move:[P2, P3:2]");
    const Node speed = block.Find("speed");
    for (const Node& item : items) {
      const auto [symbol, reps] = RefWithNumber(item);
      const Definition& path = NamedPath(capture_, item, symbol);
      Rule::Leg leg;
      const auto [kind, g] = path.body.Members().front();
      Rng rng = Rng::For(seed_, StreamTag::kObjectFlight, rule->id, rule->legs.size());
      if (PathKind(kind) == "waypoints" && g->is_object()) {
        if (speed)
          speed.Fail("the smooth flight '" + path.symbol +
                     "' has its own speed; speed times the other path kinds");
        leg.flight = ObjectFlight(path, rng);
      } else {
        leg.track = ObjectTrackOf(item, path, speed, rng);
      }
      leg.repetitions = reps < 0 ? 1 : reps;
      rule->legs.push_back(std::move(leg));
    }
  }

  // Any other path kind an object moves along: the path's points in frame order (drawn once per
  // rule and leg, as a smooth flight's intervals are), one per frame, or at the block's `speed`.
  ObjectTrack ObjectTrackOf(const Node& item,
                            const Definition& path,
                            const Node& speed,
                            Rng& rng) const {
    ObjectTrack track = paths_->Track(path, rng);
    if (track.knots.empty()) item.Fail("the path '" + path.symbol + "' has no points");
    if (!speed) {
      track.TimePerFrame(setup_.fps);
      return track;
    }
    track.TimeAtSpeed(SampleInRange(speed, KindVocabulary("object_change").Key("speed"), rng));
    return track;
  }

  // A smooth flight an object moves along (`O1:{move:[P2]}`): `waypoints:{points:[[x,y,z], ...],
  // speed, interpolation}` through the positions of the object's centre. Its intervals are drawn
  // once per rule and leg (stream (seed, object flight, rule, leg)), as a track's points are.
  Flight ObjectFlight(const Definition& path, Rng& rng) const {
    const Node g = path.body.Members().front().second;
    Flight flight;
    const bool spline = ReadFlightSettings(g, setup_.fps, rng, &flight);
    const Node points = g.Find("points");
    std::vector<Eigen::Vector3d> centres;
    for (size_t j = 0; j < points->size(); ++j) {
      const Node p = points.Item(j);
      if (!p->is_array() || p->size() != 3)
        p.Fail("an object's waypoint is the position [x,y,z] of its centre");
      centres.push_back(SampleVec3(p, rng));
    }
    flight.Build(centres,
                 std::vector<Eigen::Quaterniond>(centres.size(), Eigen::Quaterniond::Identity()),
                 spline);
    if (!(flight.length > 0)) g.Fail("the path of a moving object has length 0");
    return flight;
  }

  const Program& capture_;
  const Timeline& timeline_;
  const ChangeTargets& targets_;
  const CameraSetup& setup_;
  CameraPaths* paths_;
  uint64_t seed_;
  ClassSwaps* swaps_;
  Plan* plan_;
};

}  // namespace

bool HasObject(const Plan& plan, const ChangeTargets& targets, const std::string& symbol) {
  for (const PlannedObject& o : plan.objects)
    if (o.symbol == symbol) return true;
  return targets.scene_objects.count(symbol) > 0;
}

std::vector<Rule> ReadChangeRules(const Program& capture,
                                  const Timeline& timeline,
                                  const Timeline::IsCameraEntry& is_camera_entry,
                                  const ChangeTargets& targets,
                                  const CameraSetup& setup,
                                  CameraPaths* paths,
                                  uint64_t seed,
                                  ClassSwaps* swaps,
                                  Plan* plan) {
  RuleReader reader(capture, timeline, targets, setup, paths, seed, swaps, plan);
  for (const Definition& d : capture.definitions) {
    if (d.kind != "collection") continue;
    for (const auto& [key, value] : d.body.Members())
      if (!is_camera_entry(key, value)) reader.ReadEntry(key, value);
  }
  return std::move(reader.rules);
}

}  // namespace lsds
