// The LSCENE/LCAP text notation and JSON form: the paper's examples, text ==
// JSON, bad inputs with exact locations and suggestions.
#include <gtest/gtest.h>

#include "generator/lang/planner.h"
#include "generator/lang/random.h"
#include "generator/lang/source.h"
#include "generator/plan/plan_json.h"
#include "tests/build_paths.h"
#include "tests/lang/plan_text.h"

namespace lsds {
namespace {

const std::string kExamples = ::lsds::testing::ExamplesDir();

using testing::PlanErrorOf;

TEST(LangParser, PaperVerbatimExamplesParseWithTypoWarnings) {
  const SourceFile scene = LoadSource(kExamples + "/paper_example1_verbatim.lscene");
  const SourceFile capture = LoadSource(kExamples + "/paper_example1_verbatim.lcap");
  // The two stray '}' and the "extent[" of the paper are accepted and reported.
  EXPECT_EQ(scene.warnings.size(), 3u);
  const OJson& io1 = scene.doc["IO1"]["object"];
  EXPECT_EQ(io1["extent"], OJson({1000, 1000, 1}));
  EXPECT_EQ(io1["position"]["ON"], "W");
  EXPECT_EQ(io1["position"]["AROUND"], "O1");
  EXPECT_EQ(scene.doc["O2"]["object"]["overlap"], true);
  EXPECT_EQ(scene.doc["O1"]["object"]["rotation"]["range"], OJson({{0, 0, 0}, {360, 360, 360}}));
  const OJson& cl = capture.doc["CL1"]["collection"];
  EXPECT_EQ(cl["C1"]["move"], OJson({"P1:3"}));
  ASSERT_TRUE(cl["O1"].is_array());
  EXPECT_EQ(cl["O1"][0]["when"]["after"], "P1:1");
  EXPECT_EQ(cl["O1"][1]["when"]["after"], "P1:2");
  EXPECT_EQ(capture.doc["P1"]["path"]["create_hemi"]["cam_radius"], OJson({1000, 2000, 5}));
  EXPECT_EQ(capture.doc["CO"]["camera"]["targets"], OJson({"O1:5"}));
}

TEST(LangParser, PaperVerbatimSceneNeedsItsUserClassesDeclared) {
  const std::string message =
      PlanErrorOf(LoadSource(kExamples + "/paper_example1_verbatim.lscene").text);
  EXPECT_NE(message.find("s.lscene:4:20: unknown class 'A'"), std::string::npos) << message;
  EXPECT_NE(message.find("classes{...}"), std::string::npos) << message;
}

TEST(LangParser, PaperVerbatimCaptureAcceptsCategoriesAndCameraAlias) {
  // The fixed scene with the verbatim capture (ONE(P), ONE(SCS), C1 for the
  // camera) plans.
  const Plan plan = MakePlan(
      kExamples + "/paper_example1.lscene", kExamples + "/paper_example1_verbatim.lcap", 4);
  EXPECT_EQ(plan.frames.size(),
            60u);  // 5 radii x 4 object angles x 1 camera angle x 3 repetitions
}

TEST(LangParser, FixedPaperExamplesPlan) {
  const Plan plan =
      MakePlan(kExamples + "/paper_example1.lscene", kExamples + "/paper_example1.lcap", 7);
  EXPECT_EQ(plan.frames.size(), 60u);
  EXPECT_EQ(plan.post_process, (std::vector<std::string>{"EdgeBlur", "CartoonStyle"}));
  EXPECT_EQ(plan.sky.color, Eigen::Vector3d(1, 1, 1));
  EXPECT_TRUE(plan.sky.cloud_type == "cumulus" || plan.sky.cloud_type == "nimbostratus");
  EXPECT_GE(plan.sky.cloud_density, 0.1);
  EXPECT_LE(plan.sky.cloud_density, 0.2);
  EXPECT_TRUE(plan.terrain.present);
  EXPECT_EQ(plan.terrain.size, Eigen::Vector2d(201, 201));
  EXPECT_EQ(plan.terrain.perlin_amplitude, 0.2);
  EXPECT_EQ(plan.terrain.material, "grassy");
  // O1 is the target with label 5; its class table entry is named after what
  // it draws: its classes{} aliases A and B.
  ASSERT_FALSE(plan.objects.empty());
  EXPECT_EQ(plan.objects[0].symbol, "O1");
  EXPECT_EQ(plan.objects[0].class_id, 5u);
  EXPECT_TRUE(plan.objects[0].target);
  EXPECT_TRUE(plan.objects[0].class_name == "jerrycan" || plan.objects[0].class_name == "barrel");
  bool found = false;
  for (const ClassInfo& c : plan.classes) found = found || (c.id == 5 && c.name == "A|B");
  EXPECT_TRUE(found);
  EXPECT_EQ(plan.classes.front().name, "terrain");
  EXPECT_FALSE(plan.objects[1].visible);  // IO1, the invisible placement zone
  // Material change after P1(1) (frames 20..), rotation added after P1(2)
  // (frames 40..).
  EXPECT_TRUE(plan.frames[19].changes.empty());
  ASSERT_EQ(plan.frames[20].changes.size(), 1u);
  EXPECT_EQ(*plan.frames[20].changes[0].material, "MetalGold");
  // The rotation, then the re-seat that keeps O1 ON the terrain.
  ASSERT_EQ(plan.frames[40].changes.size(), 3u);
  EXPECT_TRUE(plan.frames[40].changes[1].world_from_object.has_value());
  EXPECT_TRUE(plan.frames[40].changes[2].position.has_value());
  // Drawn once when it fires: the same rotation on every later frame.
  EXPECT_EQ(*plan.frames[40].changes[1].world_from_object,
            *plan.frames[59].changes[1].world_from_object);
  EXPECT_EQ(plan.frames[59].sequence, "P1(3)");
  // Instance ids unique, from 1 (terrain) on.
  EXPECT_EQ(plan.terrain.instance_id, 1u);
  for (size_t i = 0; i < plan.objects.size(); ++i) EXPECT_EQ(plan.objects[i].instance_id, i + 2);
}

nlohmann::json WithoutSources(const Plan& plan) {
  nlohmann::json j = PlanToJson(plan);
  j.erase("scene_source");
  j.erase("capture_source");
  return j;
}

TEST(LangParser, TextAndJsonFormsGiveIdenticalPlans) {
  for (const std::string name : {"paper_example1", "uav_survey"}) {
    const SourceFile scene = LoadSource(kExamples + "/" + name + ".lscene");
    const SourceFile capture = LoadSource(kExamples + "/" + name + ".lcap");
    const SourceFile scene_json = ParseSource(SourceToJson(scene).dump(2), "scene.json", true);
    const SourceFile capture_json =
        ParseSource(SourceToJson(capture).dump(2), "capture.json", true);
    for (uint64_t seed : {0ull, 1ull, 99ull}) {
      EXPECT_EQ(WithoutSources(MakePlanFromSources(scene, &capture, seed)),
                WithoutSources(MakePlanFromSources(scene_json, &capture_json, seed)))
          << name << " seed " << seed;
    }
  }
  const SourceFile rocky = LoadSource(kExamples + "/rocky_sand_clutter.lscene");
  const SourceFile rocky_json = ParseSource(SourceToJson(rocky).dump(), "rocky.json", true);
  EXPECT_EQ(WithoutSources(MakePlanFromSources(rocky, nullptr, 5)),
            WithoutSources(MakePlanFromSources(rocky_json, nullptr, 5)));
}

TEST(LangParser, KeysAcceptBothSeparatorsAndSpellings) {
  const std::string a =
      "LSCENE = ONE(W) ONE(O)\nW = terrain{size=[10,10]}\nO = "
      "object{class=cube,position={ON=W}}\n";
  const std::string b =
      "LSCENE = ONE(W) ONE(O)\nW = terrain{size:[10,10]}\nO = "
      "object{Class:cube,Position:{on:W}}\n";
  const Plan pa = MakePlanFromSources(ParseSource(a, "a", false), nullptr, 3);
  const Plan pb = MakePlanFromSources(ParseSource(b, "b", false), nullptr, 3);
  EXPECT_EQ(pa.objects[0].position, pb.objects[0].position);
}

TEST(LangParser, AnUnquotedDateIsTheDate) {
  const std::string quoted =
      "LSCENE = ONE(G) ONE(DL)\nG = georeference{latitude:48,longitude:11}\n"
      "DL = light{date:\"2026-06-21\",time:\"09:00\",utc_offset:2}\n";
  std::string unquoted = quoted;
  unquoted.replace(unquoted.find("\"2026-06-21\""), 12, "2026-06-21");
  const Plan a = MakePlanFromSources(ParseSource(quoted, "a", false), nullptr, 3);
  const Plan b = MakePlanFromSources(ParseSource(unquoted, "b", false), nullptr, 3);
  ASSERT_TRUE(b.sun.clock_utc_s.has_value());
  EXPECT_EQ(*a.sun.clock_utc_s, *b.sun.clock_utc_s);
  EXPECT_EQ(a.sun.elevation_deg, b.sun.elevation_deg);
}

struct BadInput {
  std::string scene, capture, expected;
};

TEST(LangParser, BadInputsNameTheExactPlace) {
  const std::string ok_scene =
      "LSCENE = ONE(W) ONE(O1)\nW = terrain{size:[50,50]}\nO1 = "
      "object{class:cube,position:{ON:W}}\n";
  const std::vector<BadInput> cases = {
      {"LSCENE = ONE(S)\nS = skybx{color:white}\n",
       "",
       "s.lscene:2:5: unknown kind 'skybx' for S (did you mean 'skybox'?)"},
      {"LSCENE = ONE(S)\nS = skybox{colour:white}\n",
       "",
       "s.lscene:2:12: unknown key 'colour' in S (did you mean 'color'?)"},
      {"LSCENE = ONE(S)\nS = skybox{color:white\n",
       "",
       "s.lscene:2:11: unclosed '{': expected '}' before the end of the file"},
      {"LSCENE = ONE(S)\nS = skybox{color:white,,}\n",
       "",
       "s.lscene:2:24: expected a key or '}', found ','"},
      {"LSCENE = ONE(O1)\nO1 = object{class:rok}\n",
       "",
       "s.lscene:2:19: unknown class 'rok' (did you mean 'rock'?)"},
      {"LSCENE = ONE(O1)\nO1 = object{class:cube,position:{ON:W}}\n",
       "",
       "s.lscene:2:37: O1 refers to undefined symbol 'W'"},
      {"LSCENE = ONE(O1) ONE(O2)\nO1 = object{class:cube,position:{ON:O2}}\nO2 "
       "= object{class:cube}\n",
       "",
       "s.lscene:2:37: O1 refers to 'O2' before its definition"},
      {"LSCENE = ONE(O1)\nO1 = object{class:cube,position:{ON:O1}}\n",
       "",
       "s.lscene:2:37: O1 refers to itself"},
      {"LSCENE = ONE(W) MANY(O2)\nW = terrain{size:[10,10]}\nO2 = "
       "object{class:{bush:0.5,rok:0.5}}\n",
       "",
       "s.lscene:3:29: unknown class 'rok' (did you mean 'rock'?)"},
      {"LSCENE = ONE(W) ONE(Q)\nW = terrain{size:[10,10]}\n",
       "",
       "s.lscene:1:21: the start rule names undefined symbol 'Q'"},
      {"LSCENE = ONE(W) ONE(O1) ONE(O2)\nW = terrain{size:[10,10]}\nO1 = "
       "object{class:cube,position:{ON:W}}\n"
       "O2 = "
       "object{class:cube,position:{ON:W,IN:O1,within:[[20,20,-5],[30,30,5]]}}"
       "\n",
       "",
       "s.lscene:4:52: O2 copy 1: the position space is empty after within"},
      {"LSCENE = ONE(W) MANY(O2, 200)\nW = terrain{size:[4,4]}\nO2 = "
       "object{class:cube,position:{ON:W},retries:5}\n",
       "",
       "s.lscene:3:33: O2: cannot place copy"},
      {"LSCENE = ONE(S)\nS = skybox{clouds:{type:{cumulus:0.5,cirus:0.5}}}\n",
       "",
       "s.lscene:2:38: unknown cloud type 'cirus' (did you mean 'cirrus'?)"},
      {"LSCENE = ONE(S)\nS = skybox{intensity:[2,1]}\n",
       "",
       "s.lscene:2:22: interval [lo, hi] needs lo <= hi"},
      {"LSCENE = ONE(S)\nS = skybox{intensity:@}\n", "", "s.lscene:2:22: unexpected character '@'"},
      {"LSCENE = ONE(S)\nS = light{time:08:00}\n",
       "",
       "s.lscene:2:16: a value with ':' in it is written in quotes, e.g. a time of day "
       "time:\"08:00\""},
      {ok_scene,
       "LCAP = ONE(CO)\nCO = camera{csettings:{fov:30,rez:[10,10]}}\n",
       "c.lcap:2:31: unknown key 'rez' in camera settings (did you mean "
       "'res'?)"},
      {ok_scene,
       "LCAP = ONE(CO)\nCO = camera{targets:[O2:5]}\n",
       "c.lcap:2:22: target 'O2' is not an object of the scene (did you mean "
       "'O1'?)"},
      {ok_scene,
       "LCAP = ONE(P1) ONE(CL)\nP1 = "
       "path{hemi:{cam_radius:[1,2,2],obj_angle:[0,360,4],cam_angle:45}}\nCL = "
       "collection{CO:{move:[P2:2]}}\n",
       "c.lcap:3:27: 'P2' is not a path (did you mean 'P1'?)"},
      {ok_scene,
       "LCAP = ONE(P1) ONE(CL)\nP1 = "
       "path{hemi:{cam_radius:[1,2,2],obj_angle:[0,360,4],cam_angle:45}}\nCL = "
       "collection{CO:{move:[P1:2]},O1:{after:P1:3,material:gold}}\n",
       "c.lcap:3:44: path 'P1' has no repetition 3"},
      {ok_scene,
       "LCAP = ONE(P1)\nP1 = "
       "path{hemi:{cam_radius:[1,2,2],obj_angle:[0,360,4]}}\n",
       "c.lcap:2:16: create hemi needs cam_radius, obj_angle and cam_angle"},
      {ok_scene,
       "LCAP = ONE(P1)\nP1 = path{gride:{}}\n",
       "c.lcap:2:11: unknown key 'gride' in path P1 (did you mean 'grid'?)"},
  };
  for (const BadInput& c : cases) {
    const std::string message = PlanErrorOf(c.scene, c.capture);
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << "got: " << message << "\nexpected: " << c.expected;
  }
}

TEST(LangParser, JsonErrorsNameThePointer) {
  const SourceFile s =
      ParseSource(R"({"LSCENE":[{"ONE":"S"}],"S":{"skybox":{"colr":"white"}}})", "s.json", true);
  try {
    MakePlanFromSources(s, nullptr, 0);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("s.json#/S/skybox/colr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("did you mean 'color'"), std::string::npos) << e.what();
  }
  const std::string schema_error = [] {
    try {
      MakePlanFromSources(
          ParseSource(R"({"LSCENE":[{"ONE":"S","count":3}]})", "t.json", true), nullptr, 0);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  EXPECT_NE(schema_error.find("t.json#/LSCENE/0"), std::string::npos) << schema_error;
  EXPECT_THROW(ParseSource("{\"LSCENE\": [", "u.json", true), Error);
}

TEST(LangParser, GarbageNeverCrashes) {
  Rng rng(7);
  const std::string alphabet = "LSCENE=ONE(MANY)O1{}[]:,=.-0123456789 \nabc\"#";
  for (int i = 0; i < 2000; ++i) {
    std::string text;
    const int n = static_cast<int>(rng.UniformInt(0, 80));
    for (int j = 0; j < n; ++j)
      text += alphabet[static_cast<size_t>(rng.UniformInt(0, alphabet.size() - 1))];
    try {
      const SourceFile s = ParseSource(text, "g", false);
      MakePlanFromSources(s, nullptr, 0);
    } catch (const Error&) {
    }
  }
}

}  // namespace
}  // namespace lsds
