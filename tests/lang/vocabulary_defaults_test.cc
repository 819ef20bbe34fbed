// The defaults the vocabulary table states (`Row(...).Default(v)`; docs/languages.md, `lsds
// language --json`) are the evaluators' own: for every key with one, a program that gives the key
// its default plans byte for byte as the program without the key. A default said in words
// (`Row(...).DefaultIs(words)`) is checked the same way with the value it stands for in a program.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "generator/lang/random.h"
#include "generator/lang/scene.h"
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

// A key of the terrain's vegetation block.
Program VegetationKey() {
  return [](const std::string& key) {
    return std::make_pair(
        "LSCENE = ONE(W)\nW = terrain{size:[20,20],vegetation:{density:1" + After(key) + "}}\n",
        kCamera);
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
      {{"vegetation", "kind"}, VegetationKey()},
      {{"vegetation", "height"}, VegetationKey()},
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

// A program without the key and the same program with the value a default in words stands for.
struct Described {
  std::pair<std::string, std::string> without, with;
};

std::string Vector(const Eigen::Vector3d& v) {
  return nlohmann::json({v.x(), v.y(), v.z()}).dump();
}

// The scene with one object O (`o_keys` inside its braces) on the ground.
std::string OneObject(const std::string& o_keys) {
  return "LSCENE = ONE(W) ONE(O)\n" + kGround + "O = object{" + o_keys + "}\n";
}

// Every (kind, key) with a default in words, and programs that give it its value (planned with
// seed 3).
const std::map<std::pair<std::string, std::string>, std::vector<Described>>& DescribedPrograms() {
  const std::string crate = Vector(BuiltinClasses().at("crate"));
  const std::string terrain_seed =
      std::to_string(MixKey(3, static_cast<uint64_t>(StreamTag::kTerrain)) >> 11);
  const std::string hemi =
      "P = path{create hemi:{cam radius:[20,20,1],obj angle:[0,270,4],cam angle:[40,40,1]%}}\n";
  auto capture = [](std::string text, const std::string& key) {
    text.replace(text.find('%'), 1, key);
    return text;
  };
  const std::string targets = "LCAP = ONE(CO) ONE(P)\nCO = camera{targets:[O]}\n";
  const std::string moving =
      "LCAP = ONE(CO) ONE(P) ONE(R) ONE(CL)\nCO = camera{csettings:{res:[32,24]}}\n"
      "P = path{waypoints:[[0,0,40],[0,0,40],[0,0,40],[0,0,40]]}\n"
      "R = path{waypoints:[[0,0,0],[10,0,0],[20,0,0]]}\n"
      "CL = collection{CO:{move:[P]},O:{move:[R]%}}\n";
  static const std::map<std::pair<std::string, std::string>, std::vector<Described>> programs = {
      {{"terrain", "seed"},
       {{{"LSCENE = ONE(W)\nW = terrain{size:[200,200],perlin:2}\n", kCamera},
         {"LSCENE = ONE(W)\nW = terrain{size:[200,200],perlin:2,seed:" + terrain_seed + "}\n",
          kCamera}}}},
      {{"object", "extent"},
       {{{OneObject("class:crate"), kCamera},
         {OneObject("class:crate,extent:" + crate), kCamera}}}},
      {{"object", "target"},
       {{{OneObject("class:cube"), kCamera}, {OneObject("class:cube,target:true"), kCamera}},
        // With targets, an object not listed gets none.
        {{"LSCENE = ONE(W) ONE(O) ONE(Q)\n" + kGround + "O = object{class:cube}\n" +
              "Q = object{class:crate}\n",
          targets + "P = path{create point:{position:[0,0,30]}}\n"},
         {"LSCENE = ONE(W) ONE(O) ONE(Q)\n" + kGround + "O = object{class:cube}\n" +
              "Q = object{class:crate,target:false}\n",
          targets + "P = path{create point:{position:[0,0,30]}}\n"}}}},
      {{"blueprint_member", "extent"},
       {{{"LSCENE = ONE(W) ONE(C)\n" + kGround +
              "B = blueprint{X:{class:crate}}\nC = object{class:B}\n",
          kCamera},
         {"LSCENE = ONE(W) ONE(C)\n" + kGround + "B = blueprint{X:{class:crate,extent:" + crate +
              "}}\nC = object{class:B}\n",
          kCamera}}}},
      {{"create_hemi", "center"},
       {{{OneObject("class:cube"), "LCAP = ONE(P)\n" + capture(hemi, "")},
         {OneObject("class:cube"), "LCAP = ONE(P)\n" + capture(hemi, ",center:[0,0,0]")}},
        {{OneObject("class:cube,position:{ON:W,within:[[5,6,-10],[5,6,10]]}"),
          targets + capture(hemi, "")},
         {OneObject("class:cube,position:{ON:W,within:[[5,6,-10],[5,6,10]]}"),
          targets + capture(hemi, ",center:O")}}}},
      {{"create_point", "rotation"},
       {{{OneObject("class:cube"), "LCAP = ONE(P)\nP = path{create point:{position:[0,0,30]}}\n"},
         {OneObject("class:cube"),
          "LCAP = ONE(P)\nP = path{create point:{position:[0,0,30],rotation:[0,-90,0]}}\n"}}}},
      {{"create_path", "rotation"},
       {{{OneObject("class:cube"),
          "LCAP = ONE(P)\nP = path{create path:{space:[[-5,-5,20],[5,5,30]],points:3}}\n"},
         {OneObject("class:cube"),
          "LCAP = ONE(P)\nP = path{create path:{space:[[-5,-5,20],[5,5,30]],points:3,"
          "rotation:[0,-90,0]}}\n"}}}},
      // 10 m between points at the default 10 fps: 100 m/s.
      {{"object_change", "speed"},
       {{{OneObject("class:cube"), capture(moving, "")},
         {OneObject("class:cube"), capture(moving, ",speed:100")}}}},
  };
  return programs;
}

TEST(VocabularyDefaults, ADefaultInWordsPlansAsTheValueItStandsFor) {
  int checked = 0;
  for (const KindSpec& kind : Vocabulary())
    for (const KeySpec& key : kind.keys) {
      if (key.default_text.empty()) continue;
      EXPECT_TRUE(key.default_value.is_null()) << kind.id << "." << key.name << ": both defaults";
      const auto programs = DescribedPrograms().find({kind.id, key.name});
      ASSERT_NE(programs, DescribedPrograms().end())
          << kind.id << "." << key.name << " has a default in words but no program here";
      for (const Described& d : programs->second)
        EXPECT_EQ(PlanJson(d.with), PlanJson(d.without))
            << kind.id << "." << key.name << " (" << key.default_text << ")\nscene:\n"
            << d.with.first << "capture:\n"
            << d.with.second;
      ++checked;
    }
  EXPECT_EQ(checked, static_cast<int>(DescribedPrograms().size()));
}

}  // namespace
}  // namespace lsds
