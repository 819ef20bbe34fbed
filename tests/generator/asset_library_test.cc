// The user asset library (generator/scene/asset_library.h) and the built-in
// classes' other spellings: selection by tag, name and pattern, units and up
// axis, located errors, and a generated collection that validates.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "../test_util.h"
#include "generator/lang/planner.h"
#include "generator/scene/object_library.h"
#include "libs/util/error.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;

// An OBJ box from (0,0,0) to `size` in the file's units.
void WriteBoxObj(const fs::path& path, double x, double y, double z) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path);
  for (int i = 0; i < 8; ++i)
    out << "v " << (i & 1 ? x : 0) << " " << (i & 2 ? y : 0) << " " << (i & 4 ? z : 0) << "\n";
  // Six faces as quads (1-based corners: bit 0 = x, bit 1 = y, bit 2 = z).
  out << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
}

// Three assets: a 1 m cube in centimetres (y-up), a slab 2 m x 0.5 m (up, in
// y) x 1 m (in z) in metres with y-up (world extent 2 x 1 x 0.5), and a pole
// 0.2 x 0.2 x 3 m in millimetres, z-up.
class AssetLibraryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const fs::path lib = dir_ / "lib";
    WriteBoxObj(lib / "clutter" / "cube_cm.obj", 100, 100, 100);
    WriteBoxObj(lib / "clutter" / "slab_y.obj", 2, 0.5, 1);
    WriteBoxObj(lib / "trees" / "pole_mm.obj", 200, 200, 3000);
    WriteManifest(R"({"assets": [
      {"file": "clutter/cube_cm.obj", "class": "crate", "tags": ["desert", "clutter"],
       "unit": "cm", "up": "y"},
      {"file": "clutter/slab_y.obj", "class": "rocks", "tags": ["desert", "rock"], "up": "y"},
      {"file": "trees/pole_mm.obj", "class": "tree", "tags": ["forest"], "unit": "mm", "up": "z"}
    ]})");
  }
  void WriteManifest(const std::string& text) {
    std::ofstream(dir_ / "lib" / "lsds_assets.json") << text;
  }
  Plan PlanScene(const std::string& objects, uint64_t seed) {
    std::ofstream(dir_ / "s.lscene") << "LSCENE = ONE(W) MANY(O, 12)\n"
                                        "L = asset_library{path:lib}\n"
                                        "W = terrain{size:[100,100]}\n"
                                     << objects << "\n";
    return MakePlan(dir_ / "s.lscene", std::nullopt, seed);
  }
  std::string ErrorOf(const std::string& objects) {
    try {
      PlanScene(objects, 1);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  }
  std::string ClassOf(const Plan& plan, uint32_t id) {
    for (const ClassInfo& c : plan.classes)
      if (c.id == id) return c.name;
    return "";
  }
  testing::TempDir dir_;
};

TEST_F(AssetLibraryTest, TagsSelectOnlyAssetsCarryingEveryTag) {
  std::set<std::string> desert;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const Plan rock = PlanScene("O = object{class:{tags:[desert,rock]},overlap:true}", seed);
    ASSERT_EQ(rock.objects.size(), 12u);
    for (const PlannedObject& o : rock.objects) {
      EXPECT_EQ(fs::path(o.class_name).filename(), "slab_y.obj");
      EXPECT_EQ(ClassOf(rock, o.class_id), "rock");  // `rocks` is the built-in rock's class
    }
    const Plan any = PlanScene("O = object{class:{tags:desert},overlap:true}", seed);
    for (const PlannedObject& o : any.objects) {
      EXPECT_EQ(fs::path(o.class_name).parent_path().filename(), "clutter") << o.class_name;
      desert.insert(fs::path(o.class_name).filename());
    }
    // The same seed draws the same assets.
    const Plan again = PlanScene("O = object{class:{tags:desert},overlap:true}", seed);
    for (size_t i = 0; i < any.objects.size(); ++i)
      EXPECT_EQ(again.objects[i].class_name, any.objects[i].class_name);
  }
  EXPECT_EQ(desert, (std::set<std::string>{"cube_cm.obj", "slab_y.obj"}));
}

TEST_F(AssetLibraryTest, PatternsMatchWholeRelativePathsAndNamesPickOne) {
  std::set<std::string> drawn;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const Plan plan = PlanScene(R"(O = object{class:{"clutter/.*\\.obj":1},overlap:true})", seed);
    for (const PlannedObject& o : plan.objects) drawn.insert(fs::path(o.class_name).filename());
  }
  EXPECT_EQ(drawn, (std::set<std::string>{"cube_cm.obj", "slab_y.obj"}));
  const Plan trees = PlanScene(R"(O = object{class:"t.*/pole.*",overlap:true})", 3);
  for (const PlannedObject& o : trees.objects) EXPECT_EQ(ClassOf(trees, o.class_id), "tree");
  const Plan named = PlanScene("O = object{class:pole_mm,overlap:true}", 3);
  for (const PlannedObject& o : named.objects)
    EXPECT_EQ(o.class_name, ((dir_ / "lib" / "trees" / "pole_mm.obj").lexically_normal()));
}

TEST_F(AssetLibraryTest, UnitsAndUpAxisGiveTheBoxInMetres) {
  const Plan plan =
      PlanScene(R"(O = object{class:{cube_cm:1,slab_y:1,pole_mm:1},overlap:true})", 5);
  std::set<std::string> seen;
  for (const PlannedObject& o : plan.objects) {
    const std::string name = fs::path(o.class_name).stem();
    seen.insert(name);
    const Eigen::Vector3d expected = name == "cube_cm"  ? Eigen::Vector3d(1, 1, 1)
                                     : name == "slab_y" ? Eigen::Vector3d(2, 1, 0.5)
                                                        : Eigen::Vector3d(0.2, 0.2, 3);
    EXPECT_TRUE(o.extent.isApprox(expected, 1e-9)) << name << ": " << o.extent.transpose();
    EXPECT_NEAR(o.position.z(), 0.5 * expected.z(), 1e-9);  // standing on flat ground
  }
  EXPECT_EQ(seen.size(), 3u);
  // The renderer's loader turns the y-up slab upright: its thin side (0.5 m) is up.
  const gen::TriangleMesh slab =
      gen::LoadMeshFileNative((dir_ / "lib" / "clutter" / "slab_y.obj").string(), "test");
  Eigen::Vector3f lo = slab.positions[0], hi = lo;
  for (const Eigen::Vector3f& p : slab.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  EXPECT_TRUE((hi - lo).isApprox(Eigen::Vector3f(2, 1, 0.5), 1e-6)) << (hi - lo).transpose();
}

TEST_F(AssetLibraryTest, BadSelectionsAndManifestsAreLocated) {
  EXPECT_NE(
      ErrorOf("O = object{class:{tags:[desrt]}}").find("s.lscene:4:25: no asset of the library"),
      std::string::npos)
      << ErrorOf("O = object{class:{tags:[desrt]}}");
  EXPECT_NE(ErrorOf("O = object{class:{tags:[desrt]}}").find("did you mean 'desert'"),
            std::string::npos);
  const std::string nothing = ErrorOf(R"(O = object{class:{"props/.*\\.obj":1}})");
  EXPECT_NE(nothing.find("s.lscene:4:19: the pattern 'props/.*\\.obj' matches no asset"),
            std::string::npos)
      << nothing;
  EXPECT_NE(ErrorOf("O = object{class:{tags:[forest,rock]}}").find("has all the tags"),
            std::string::npos);
  WriteManifest(R"({"assets": [{"file": "clutter/cube_cm.obj", "class": "crate", "unit": "km"}]})");
  const std::string unit = ErrorOf("O = object{class:cube_cm}");
  EXPECT_NE(unit.find("lsds_assets.json#/assets/0/unit: unit must be m, cm or mm"),
            std::string::npos)
      << unit;
  WriteManifest(R"({"assets": [{"file": "clutter/nope.obj", "class": "crate"}]})");
  EXPECT_NE(ErrorOf("O = object{class:cube_cm}").find("lsds_assets.json#/assets/0/file"),
            std::string::npos);
  WriteManifest(R"({"assets": [)");
  EXPECT_NE(ErrorOf("O = object{class:cube_cm}").find("lsds_assets.json: not valid JSON"),
            std::string::npos);
}

TEST_F(AssetLibraryTest, AFolderWithoutAManifestIsALibraryByItsFolders) {
  const fs::path lib = dir_ / "plain";
  WriteBoxObj(lib / "vehicles" / "car_a.obj", 4, 2, 1.5);
  WriteBoxObj(lib / "vehicles" / "van_b.obj", 5, 2, 2);
  WriteBoxObj(lib / "nature" / "rocks" / "boulder.obj", 1, 1, 0.8);
  WriteBoxObj(lib / "sign.obj", 0.1, 0.6, 2);
  std::ofstream(lib / "readme.txt") << "not a mesh\n";
  auto plan_with = [&](const std::string& objects) {
    std::ofstream(dir_ / "p.lscene") << "LSCENE = ONE(W) MANY(O, 12)\n"
                                        "L = asset_library{path:plain}\n"
                                        "W = terrain{size:[100,100]}\n"
                                     << objects << "\n";
    return MakePlan(dir_ / "p.lscene", std::nullopt, 4);
  };
  // Tags are the folders on the path; the class is the folder a file lies in.
  const Plan vehicles = plan_with("O = object{class:{tags:[vehicles]}}");
  std::set<std::string> files;
  for (const PlannedObject& o : vehicles.objects) {
    if (o.symbol != "O") continue;
    files.insert(fs::path(o.class_name).filename().string());
    EXPECT_EQ(ClassOf(vehicles, o.class_id), "vehicles");
  }
  EXPECT_EQ(files, (std::set<std::string>{"car_a.obj", "van_b.obj"}));
  const Plan rocks = plan_with("O = object{class:{tags:[nature,rocks]}}");
  EXPECT_EQ(ClassOf(rocks, rocks.objects.back().class_id), "rock");  // the built-in's spelling
  EXPECT_NEAR((rocks.objects.back().extent - Eigen::Vector3d(1, 1, 0.8)).norm(), 0, 1e-6);
  // A pattern over the relative paths, and a file at the root named by its stem.
  const Plan pattern = plan_with(R"(O = object{class:{"vehicles/van_.*":1}})");
  EXPECT_EQ(fs::path(pattern.objects.back().class_name).filename(), "van_b.obj");
  const Plan sign = plan_with("O = object{class:sign}");
  EXPECT_EQ(ClassOf(sign, sign.objects.back().class_id), "sign");
  // An empty folder is neither kind of library.
  fs::create_directories(dir_ / "empty");
  std::ofstream(dir_ / "e.lscene") << "LSCENE = ONE(O)\nL = asset_library{path:empty}\n"
                                      "O = object{class:cube}\n";
  try {
    MakePlan(dir_ / "e.lscene", std::nullopt, 1);
    ADD_FAILURE() << "an empty library folder planned";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("neither a manifest"), std::string::npos) << e.what();
  }
}

TEST_F(AssetLibraryTest, GeneratedCollectionValidatesAndRecordsTheAsset) {
  std::ofstream(dir_ / "s.lscene") << "LSCENE = ONE(W) ONE(O)\n"
                                      "L = asset_library{path:lib}\n"
                                      "W = terrain{size:[40,40]}\n"
                                      "O = object{class:{tags:[desert,rock]},"
                                      "position:{ON:W,within:[[-0.1,-0.1,-9],[0.1,0.1,9]]}}\n";
  std::ofstream(dir_ / "c.lcap")
      << "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
         "CO = camera{csettings:{fov:60,res:[64,48],fps:1},targets:[O]}\n"
         "P = path{waypoints:[[0,0,12,0,-90,0],[1,0,12,0,-90,0]]}\n"
         "CL = collection{CO:{move:[P]}}\n";
  const std::string out = (dir_ / "out").string();
  const std::string lsds = testing::LsdsBinary();
  const auto generated =
      testing::RunCommandLine(lsds + " generate " + (dir_ / "s.lscene").string() + " " +
                              (dir_ / "c.lcap").string() + " -o " + out + " --spp 1 -q");
  ASSERT_EQ(generated.exit_code, 0) << generated.output;
  const auto validated = testing::RunCommandLine(lsds + " validate " + out + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
  std::ifstream in(dir_ / "out" / "collection.json");
  const nlohmann::json collection = nlohmann::json::parse(in);
  // The truth records the asset drawn, its class and its box in metres.
  const nlohmann::json& object = collection["frames"][0]["objects"][0];
  EXPECT_EQ(fs::path(object["asset"].get<std::string>()).lexically_normal().generic_string(),
            (dir_ / "lib" / "clutter" / "slab_y.obj").lexically_normal().generic_string());
  EXPECT_EQ(collection["classes"][1]["name"], "rock");
  EXPECT_EQ(object["class_id"], collection["classes"][1]["id"]);
  const Eigen::Vector3d half(object["obb"]["half_extents"][0].get<double>(),
                             object["obb"]["half_extents"][1].get<double>(),
                             object["obb"]["half_extents"][2].get<double>());
  EXPECT_TRUE(half.isApprox(Eigen::Vector3d(1, 0.5, 0.25), 1e-9)) << half.transpose();
  EXPECT_GT(object["visible_pixels"].get<int64_t>(), 0);
}

// An LCAP class swap draws from the scene's library by tags and by pattern,
// per frame with `during`, the same draws for the same seed.
TEST_F(AssetLibraryTest, CaptureClassSwapsDrawFromTheLibrary) {
  std::ofstream(dir_ / "s.lscene") << "LSCENE = ONE(W) MANY(O, 8)\n"
                                      "L = asset_library{path:lib}\n"
                                      "W = terrain{size:[100,100]}\n"
                                      "O = object{class:cube,overlap:true}\n";
  auto swaps = [this](const std::string& cls, uint64_t seed) {
    std::ofstream(dir_ / "c.lcap") << "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
                                      "CO = camera{csettings:{fov:60,res:[32,24],fps:1}}\n"
                                      "P = path{waypoints:[[0,0,30,0,-90,0],[6,0,30,0,-90,0]]}\n"
                                      "CL = collection{CO:{move:[P]},O:{during:P,class:"
                                   << cls << "}}\n";
    const Plan plan = MakePlan(dir_ / "s.lscene", dir_ / "c.lcap", seed);
    std::vector<std::pair<std::string, std::string>> drawn;  // (file name, class)
    for (const PlannedFrame& f : plan.frames)
      for (const ObjectChange& c : f.changes) {
        if (!c.asset) continue;
        std::string name;
        for (const ClassInfo& k : plan.classes)
          if (c.class_id && k.id == *c.class_id) name = k.name;
        drawn.emplace_back(fs::path(*c.asset).filename().string(), name);
      }
    return drawn;
  };
  const auto rocks = swaps("{tags:[desert,rock]}", 5);
  ASSERT_FALSE(rocks.empty());
  for (const auto& [file, cls] : rocks) {
    EXPECT_EQ(file, "slab_y.obj");
    EXPECT_EQ(cls, "rock");
  }
  const auto clutter = swaps(R"({"clutter/.*\\.obj":1})", 5);
  std::set<std::string> files;
  for (const auto& [file, cls] : clutter) {
    files.insert(file);
    EXPECT_EQ(cls, file == "slab_y.obj" ? "rock" : "crate");
  }
  EXPECT_EQ(files, (std::set<std::string>{"cube_cm.obj", "slab_y.obj"}));
  EXPECT_EQ(swaps(R"({"clutter/.*\\.obj":1})", 5), clutter);  // deterministic
  EXPECT_NE(swaps(R"({"clutter/.*\\.obj":1})", 6), clutter);
}

// The paper writes `rocks`: the same class as `rock`, one class id.
TEST(ClassSpellings, PluralAndSingularResolveToOneClass) {
  const SourceFile scene = ParseSource(
      "LSCENE = ONE(W) MANY(O2, 20) MANY(O3, 5)\nW = terrain{size:[50,50]}\n"
      "O2 = object{class:{bush:0.5,rocks:0.5},overlap:true}\n"
      "O3 = object{class:rock,overlap:true}\n",
      "s.lscene",
      false);
  const Plan plan = MakePlanFromSources(scene, nullptr, 7);
  std::set<uint32_t> rock_ids;
  for (const PlannedObject& o : plan.objects) {
    EXPECT_NE(o.class_name, "rocks");
    if (o.class_name == "rock") rock_ids.insert(o.class_id);
  }
  EXPECT_EQ(rock_ids.size(), 1u);
  for (const ClassInfo& c : plan.classes) EXPECT_NE(c.name, "rocks");
  for (const auto& [alias, canonical] : gen::ClassNameAliases())
    EXPECT_EQ(gen::CanonicalClassName(alias), canonical);
  EXPECT_EQ(gen::CanonicalClassName("people"), "person");
  EXPECT_EQ(gen::CanonicalClassName("rokcs"), "");
}

}  // namespace
}  // namespace lsds
