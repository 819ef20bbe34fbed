// The scene changes of a capture (docs/languages.md, "Scene changes"): each collection entry that
// names an object, an environment symbol or a scene change set becomes a rule, with its timing,
// its change keys and, for an object that moves, the flights it follows. Every value is checked
// when the rule is read, so that a bad value is reported at once, not on some frame.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "generator/lang/capture/camera_paths.h"
#include "generator/lang/capture/camera_setup.h"
#include "generator/lang/capture/class_swaps.h"
#include "generator/lang/capture/flight.h"
#include "generator/lang/capture/timeline.h"

namespace lsds {

struct Rule {
  std::string object_symbol;     // the object, or the environment symbol
  std::string environment_kind;  // skybox, light, ...: an environment change
  Node block;                    // the change keys
  RuleTiming when;
  uint64_t id = 0;  // 1-based, in reading order: names the rule's random streams
  // An object's `move:[P2, P3:2]`: the paths it follows from `when.begin`, one after the other,
  // each repeated: a smooth flight at its speed, or the track of any other path kind, one point
  // per frame (object_track.h).
  struct Leg {
    Flight flight;
    std::optional<ObjectTrack> track;  // set: the leg follows the track, not `flight`
    int64_t repetitions = 1;
  };
  std::vector<Leg> legs;
  bool heading = false;  // the object turns to its direction of travel
  // A terrain change of the ground's shape: in effect from a shot's first frame to a shot's first
  // frame (or the end), drawn once when it takes effect (docs/languages.md, "Terrain shape
  // changes").
  bool terrain_shape = false;
};

// What a collection entry may name besides the camera.
struct ChangeTargets {
  std::set<std::string> scene_objects;                     // object symbols of the scene
  std::map<std::string, std::string> environment_symbols;  // symbol -> environment kind
};

// The rules of every collection of `capture` in file order; entries for which `is_camera_entry`
// holds are the camera's moves (the timeline's), not rules. Class swaps are declared in `swaps`;
// `plan` gives the objects and the environment the values are checked against; `paths` makes the
// tracks of objects moving along paths other than smooth flights.
std::vector<Rule> ReadChangeRules(const Program& capture,
                                  const Timeline& timeline,
                                  const Timeline::IsCameraEntry& is_camera_entry,
                                  const ChangeTargets& targets,
                                  const CameraSetup& setup,
                                  CameraPaths* paths,
                                  uint64_t seed,
                                  ClassSwaps* swaps,
                                  Plan* plan);

// Whether `symbol` names an object of the plan or the scene.
bool HasObject(const Plan& plan, const ChangeTargets& targets, const std::string& symbol);

}  // namespace lsds
