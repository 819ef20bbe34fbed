// The truth gate (docs/generator.md, "The truth gate"):
// every capture kind the languages can express, with and without timed scene
// changes, and every example, generated small and run through
// `lsds validate --fail-on warning`, the way a team gates training in CI.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "../test_util.h"
#include "tests/build_paths.h"

namespace lsds {
namespace {

using testing::LsdsBinary;
using testing::RunCommandLine;
using testing::TempDir;

const std::string kExamples = ::lsds::testing::ExamplesDir();

// Hilly terrain, objects ON it (a mixed-class symbol, a cube) and an
// invisible helper, as UAV scenes have them.
const char* kScene = R"(
LSCENE = ONE(S) ONE(DL) ONE(W) MANY(O1, 4) ONE(O2) ONE(H)
S = skybox{color:blue,clouds:{type:cumulus,density:[0.1,0.3]}}
DL = light{elevation:[35,55],azimuth:[90,270],intensity:94248}
W = terrain{size:[80,80],height:{perlin:{amplitude:2,frequency:0.05}},material:grassy}
O1 = object{class:{barrel:0.5,tire:0.5},rotation:[0,0,[0,360]],position:{ON:W,within:[[-10,-10,-100],[10,10,100]]}}
O2 = object{class:cube,extent:[2,2,2],position:{ON:W,within:[[-4,-4,-100],[4,4,100]]}}
H = object{class:sphere,visible:false,position:{ON:W}}
)";

struct CaptureCase {
  std::string name;
  std::string path;  // the body of `P = path{...}`
};

void PrintTo(const CaptureCase& c, std::ostream* os) { *os << c.name; }

// One case per path generator of docs/languages.md.
const std::vector<CaptureCase>& Cases() {
  static const std::vector<CaptureCase> cases = {
      {"hemi",
       "create hemi:{cam radius:[25,25,1],obj angle:[0,360,4],cam angle:[40,"
       "60,2],center:[0,0,0]}"},
      {"grid", "grid:{x:[-10,10,3],y:[-10,10,2],altitude:[25,35,2],perturb:[1,1,0.3]}"},
      {"increment_points", "increment points:{start:[-8,-8,30],step:[8,8,0],count:[3,2,1]}"},
      {"random",
       "random:{count:[3,6],x:[-10,10],y:[-10,10],altitude:[20,40],off_nadir:["
       "0,"
       "30]}"},
      {"create_point",
       "point:{position:[[-5,-5,25],[5,5,35]],rotation:[0,[-90,-60],[0,360]],"
       "count:4}"},
      {"waypoints",
       "waypoints:[[0,-12,25],[0,-10,25],[1,-8,25,0,-70,10],{position:[10,0,20]"
       ","
       "look_at:O2}]"},
  };
  return cases;
}

std::string Capture(const CaptureCase& c, bool changes) {
  std::ostringstream lcap;
  lcap << "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
       << "CO = camera{csettings:{fov:60,res:[160,120]},targets:[O1,O2:7]}\n"
       << "P = path{" << c.path << "}\n";
  if (changes) {
    // The path flown twice. During the first instance the cube drives along
    // a road (a moving object) and O1 is re-scattered on every frame; from
    // the second instance on: a doubled cube of another asset, a turned and
    // re-painted O1 on every frame, a shifted cube, hidden copies.
    lcap << "ROAD = path{waypoints:{points:[[-12,-14,0],[12,-14,0]],"
            "speed:6}}\n"
         << "CL = collection{CO:{move:[P:2]},"
         << "O2:{during:P:1,move:[ROAD],heading:true},"
            "{after:P:1,scale:[2,2,2]},{after:P:1,offset:[1.5,-1,0]},"
            "{after:P:1,class:sphere},"
         << "O1:{during:P:1,rescatter:true},"
            "{during:P:2,rotation:[0,[0,20],[0,360]],material:{rust:0.5,"
            "plastic:0.5}},{after:P:1,visible:false}}\n";
  } else {
    lcap << "CL = collection{CO:{move:[P]}}\n";
  }
  return lcap.str();
}

void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// Generates SCENE/CAPTURE small and returns `lsds validate --fail-on warning`.
testing::CommandResult GenerateAndValidate(const TempDir& dir,
                                           const std::string& scene,
                                           const std::string& capture) {
  const std::string out = (dir / "collection").string();
  const auto generated = RunCommandLine(LsdsBinary() + " generate " + scene + " " + capture +
                                        " -o " + out + " --spp 1 --seed 3 -q");
  if (generated.exit_code != 0) return generated;
  return RunCommandLine(LsdsBinary() + " validate " + out + " --fail-on warning");
}

class CaptureMatrix : public ::testing::TestWithParam<std::tuple<CaptureCase, bool>> {};

TEST_P(CaptureMatrix, GeneratedCollectionPassesTheGate) {
  const auto& [c, changes] = GetParam();
  TempDir dir;
  WriteText(dir / "s.lscene", kScene);
  WriteText(dir / "c.lcap", Capture(c, changes));
  const auto result =
      GenerateAndValidate(dir, (dir / "s.lscene").string(), (dir / "c.lcap").string());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("PASS: 0 error(s), 0 warning(s)"), std::string::npos)
      << result.output;
}

INSTANTIATE_TEST_SUITE_P(Captures,
                         CaptureMatrix,
                         ::testing::Combine(::testing::ValuesIn(Cases()), ::testing::Bool()),
                         [](const auto& info) {
                           return std::get<0>(info.param).name +
                                  (std::get<1>(info.param) ? "_with_changes" : "_static");
                         });

// The examples, at 160x120 (their resolution rewritten, nothing else).
class ExampleGate : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(ExampleGate, GeneratedCollectionPassesTheGate) {
  const auto& [scene, capture] = GetParam();
  TempDir dir;
  std::ifstream in(kExamples + "/" + capture);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string small =
      std::regex_replace(text, std::regex(R"(res(olution)?:\[[0-9]+,[0-9]+\])"), "res:[160,120]");
  ASSERT_NE(small, text) << capture << " declares no resolution";
  WriteText(dir / capture, small);
  const auto result = GenerateAndValidate(dir, kExamples + "/" + scene, (dir / capture).string());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("PASS: 0 error(s), 0 warning(s)"), std::string::npos)
      << result.output;
}

INSTANTIATE_TEST_SUITE_P(
    Examples,
    ExampleGate,
    ::testing::Values(std::make_pair("uav_survey.lscene", "uav_survey.lcap"),
                      std::make_pair("uav_survey.lscene", "demo_survey.lcap"),
                      std::make_pair("paper_example1.lscene", "paper_example1.lcap"),
                      std::make_pair("rocky_sand_clutter.lscene", "rocky_sand_random.lcap"),
                      std::make_pair("field_day.lscene", "field_day.lcap"),
                      std::make_pair("field_day.lscene", "field_day_figures.lcap"),
                      std::make_pair("builtin_assets.lscene", "builtin_assets.lcap"),
                      std::make_pair("time_of_day_movers.lscene", "time_of_day_movers.lcap"),
                      std::make_pair("checkpoint_relations.lscene", "checkpoint_relations.lcap")),
    [](const auto& info) {
      std::string name = info.param.second;
      return name.substr(0, name.find('.'));
    });

TEST(TruthGate, FramesPastTheEndAreAnErrorNotAnEmptyCollection) {
  TempDir dir;
  WriteText(dir / "s.lscene", kScene);
  WriteText(dir / "c.lcap", Capture(Cases()[0], false));
  const auto result = RunCommandLine(LsdsBinary() + " generate " + (dir / "s.lscene").string() +
                                     " " + (dir / "c.lcap").string() + " -o " +
                                     (dir / "out").string() + " --frames 100:200 -q");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--frames 100:200: out of range"), std::string::npos)
      << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(TruthGate, CaptureSettingsChooseTheLayersAndTheFolder) {
  TempDir dir;
  WriteText(dir / "s.lscene", kScene);
  WriteText(dir / "c.lcap",
            "LCAP = ONE(CO) ONE(P)\n"
            "CO = camera{csettings:{res:[160,120]},targets:[O1,O2],"
            "capture:{layers:[rgb,depth,instanceid],folder:survey_a}}\n"
            "P = path{waypoints:[[0,0,30],[1,0,30]]}\n");
  const auto generated = RunCommandLine("cd " + dir.path().string() + " && " + LsdsBinary() +
                                        " generate s.lscene c.lcap --spp 1 -q");
  ASSERT_EQ(generated.exit_code, 0) << generated.output;
  const std::filesystem::path out = dir / "survey_a";
  std::set<std::string> folders;
  for (const auto& entry : std::filesystem::directory_iterator(out))
    if (entry.is_directory()) folders.insert(entry.path().filename().string());
  EXPECT_EQ(folders, (std::set<std::string>{"rgb", "depth", "instanceid"}));
  std::ifstream in(out / "collection.json");
  const auto collection = nlohmann::json::parse(in);
  EXPECT_EQ(collection["layers"].size(), 3u);
  EXPECT_EQ(collection["provenance"]["render"]["capture_settings"]["layers"],
            nlohmann::json({"rgb", "depth", "instanceid"}));
  const auto validated =
      RunCommandLine(LsdsBinary() + " validate " + out.string() + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
  // An unknown layer is a located error with a suggestion.
  WriteText(dir / "bad.lcap",
            "LCAP = ONE(CO) ONE(P)\n"
            "CO = camera{capture:{layers:[rgb,dept]}}\n"
            "P = path{waypoints:[[0,0,30]]}\n");
  const auto bad = RunCommandLine(LsdsBinary() + " plan " + (dir / "s.lscene").string() + " " +
                                  (dir / "bad.lcap").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("bad.lcap:2:"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("did you mean 'depth'"), std::string::npos) << bad.output;
}

TEST(TruthGate, FogTransmittanceIsTruthAndConvertFiltersOnIt) {
  TempDir dir;
  WriteText(dir / "s.lscene",
            "LSCENE = ONE(W) ONE(A) MANY(O, 12)\n"
            "W = terrain{size:[300,300]}\nA = atmosphere{visibility:400}\n"
            "O = object{class:cube,extent:[3,3,3],position:{ON:W,within:"
            "[[-100,-100,-100],[100,100,100]]}}\n");
  WriteText(dir / "c.lcap",
            "LCAP = ONE(CO) ONE(P)\n"
            "CO = camera{csettings:{fov:90,res:[160,120]}}\n"
            "P = path{waypoints:[[0,0,60],[0,-80,40,0,-20,0],"
            "[0,80,40,0,-20,180]]}\n");
  const auto result =
      GenerateAndValidate(dir, (dir / "s.lscene").string(), (dir / "c.lcap").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(dir / "collection" / "collection.json");
  const auto collection = nlohmann::json::parse(in);
  const double extinction = collection["frames"][0]["scene"]["atmosphere"]["extinction_per_m"];
  EXPECT_NEAR(extinction, 3.912 / 400, 1e-12);
  int64_t clear = 0, hazy = 0;
  for (const auto& frame : collection["frames"]) {
    const auto& rotation = frame["camera"]["cam_from_world"]["rotation"];
    const auto& translation = frame["camera"]["cam_from_world"]["translation"];
    Eigen::Matrix3d r;
    Eigen::Vector3d t;
    for (int i = 0; i < 3; ++i) {
      t[i] = translation[i];
      for (int j = 0; j < 3; ++j) r(i, j) = rotation[i][j];
    }
    const Eigen::Vector3d eye = -r.transpose() * t;
    for (const auto& object : frame["objects"]) {
      const Eigen::Vector3d centre(
          object["obb"]["center"][0], object["obb"]["center"][1], object["obb"]["center"][2]);
      const double expected = std::exp(-extinction * (centre - eye).norm());
      EXPECT_NEAR(object["transmittance"].get<double>(), expected, 1e-9);
      if (object["visible_pixels"].get<int64_t>() == 0) continue;
      (expected >= 0.45 ? clear : hazy) += 1;
    }
  }
  ASSERT_GT(clear, 0);
  ASSERT_GT(hazy, 0);
  const auto converted = RunCommandLine(LsdsBinary() + " convert " + (dir / "collection").string() +
                                        " --to coco --images none --min-transmittance 0.45 -o " +
                                        (dir / "coco").string());
  ASSERT_EQ(converted.exit_code, 0) << converted.output;
  int64_t annotations = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir / "coco")) {
    if (entry.path().extension() != ".json" ||
        entry.path().filename().string().rfind("instances", 0) != 0)
      continue;
    std::ifstream coco(entry.path());
    annotations += nlohmann::json::parse(coco)["annotations"].size();
  }
  EXPECT_EQ(annotations, clear);
}

}  // namespace
}  // namespace lsds
