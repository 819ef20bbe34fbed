// The defaults the vocabulary table states (`Row(...).Default(v)`; docs/languages.md, `lsds
// language --json`) are the evaluators' own: for every key with one, a program that gives the key
// its default plans byte for byte as the program without the key.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <string>
#include <utility>

#include "generator/lang/vocabulary.h"
#include "generator/plan/plan_json.h"
#include "tests/lang/plan_text.h"

namespace lsds {
namespace {

// A scene and capture around one key: `key` is "" (the key left out) or "name:value".
using Program = std::function<std::pair<std::string, std::string>(const std::string& key)>;

// The comma before a key that follows others in a block.
std::string After(const std::string& key) { return key.empty() ? "" : "," + key; }

const std::string kGround = "W = terrain{size:[200,200]}\n";
const std::string kCamera =
    "LCAP = ONE(CO) ONE(P)\nCO = camera{csettings:{res:[32,24]}}\n"
    "P = path{create point:{position:[0,0,30],count:2}}\n";

Program SceneKey(const std::string& kind) {
  return [kind](const std::string& key) {
    return std::make_pair("LSCENE = ONE(X) ONE(W)\nX = " + kind + "{" + key + "}\n" + kGround,
                          kCamera);
  };
}

// `%` in the capture is the key's slot; `after_others`: other keys come before it in its block.
Program CaptureKey(const std::string& capture_with_slot, bool after_others) {
  return [capture_with_slot, after_others](const std::string& key) {
    std::string capture = capture_with_slot;
    capture.replace(capture.find('%'), 1, after_others ? After(key) : key);
    return std::make_pair("LSCENE = ONE(O) ONE(W)\nO = object{class:cube}\n" + kGround, capture);
  };
}

// Every (kind, key) with a default, and a program that uses it.
const std::map<std::pair<std::string, std::string>, Program>& Programs() {
  static const std::map<std::pair<std::string, std::string>, Program> programs = {
      {{"skybox", "luminance"}, SceneKey("skybox")},
      {{"light", "elevation"}, SceneKey("light")},
      {{"light", "azimuth"}, SceneKey("light")},
      {{"light", "illuminance"}, SceneKey("light")},
      {{"skylight", "intensity"}, SceneKey("skylight")},
      {{"terrain", "frequency"},
       [](const std::string& key) {
         return std::make_pair(
             "LSCENE = ONE(W)\nW = terrain{size:[200,200],perlin:2" + After(key) + "}\n", kCamera);
       }},
      {{"object", "retries"},
       [](const std::string& key) {
         return std::make_pair("LSCENE = ONE(O) MANY(C, 20) ONE(W)\n" + kGround +
                                   "O = object{class:cube}\nC = object{class:cube" + After(key) +
                                   ",position:{ON:W,within:[[-20,-20,-100],[20,20,100]]}}\n",
                               kCamera);
       }},
      {{"blueprint_member", "at"},
       [](const std::string& key) {
         return std::make_pair("LSCENE = ONE(W) ONE(C)\n" + kGround +
                                   "B = blueprint{X:{class:cube" + After(key) +
                                   "},Y:{class:crate,at:[3,0,0]}}\nC = object{class:B}\n",
                               kCamera);
       }},
      {{"camera_settings", "fov"},
       CaptureKey("LCAP = ONE(CO) ONE(P)\nCO = camera{csettings:{%}}\n"
                  "P = path{create point:{position:[0,0,30]}}\n",
                  false)},
      {{"camera_settings", "res"},
       CaptureKey("LCAP = ONE(CO) ONE(P)\nCO = camera{csettings:{%}}\n"
                  "P = path{create point:{position:[0,0,30]}}\n",
                  false)},
      {{"camera_settings", "fps"},
       CaptureKey("LCAP = ONE(CO) ONE(P)\nCO = camera{csettings:{res:[32,24]%}}\n"
                  "P = path{waypoints:{points:[[0,0,30],[40,0,30]],speed:5}}\n",
                  true)},
      {{"grid", "pitch"},
       CaptureKey("LCAP = ONE(P)\nP = path{grid:{x:[0,10,5],y:[0,10,5],altitude:20%}}\n", true)},
      {{"random", "altitude"}, CaptureKey("LCAP = ONE(P)\nP = path{random:{count:4%}}\n", true)},
      {{"random", "off_nadir"}, CaptureKey("LCAP = ONE(P)\nP = path{random:{count:4%}}\n", true)},
      {{"create_point", "count"},
       CaptureKey("LCAP = ONE(P)\nP = path{create point:{position:[0,0,30]%}}\n", true)},
  };
  return programs;
}

// The plan without its sources' text (which differs by the key written).
std::string PlanJson(const std::pair<std::string, std::string>& program) {
  nlohmann::ordered_json plan = PlanToJson(testing::PlanText(program.first, program.second, 3));
  plan.erase("scene_source");
  plan.erase("capture_source");
  return plan.dump();
}

TEST(VocabularyDefaults, GivingTheDefaultPlansAsLeavingTheKeyOut) {
  int checked = 0;
  for (const KindSpec& kind : Vocabulary())
    for (const KeySpec& key : kind.keys) {
      if (key.default_value.is_null()) continue;
      const auto program = Programs().find({kind.id, key.name});
      ASSERT_NE(program, Programs().end())
          << kind.id << "." << key.name << " has a default but no program here to check it";
      const std::string value = key.default_value.dump();
      const auto without = program->second("");
      const auto with = program->second(key.name + ":" + value);
      EXPECT_EQ(PlanJson(with), PlanJson(without))
          << kind.id << "." << key.name << ":" << value << "\nscene:\n"
          << with.first << "capture:\n"
          << with.second;
      ++checked;
    }
  EXPECT_EQ(checked, static_cast<int>(Programs().size()));
}

}  // namespace
}  // namespace lsds
