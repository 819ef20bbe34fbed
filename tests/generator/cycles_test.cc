// Blender Cycles as the rgb renderer (docs/generator.md, "Blender Cycles") and the scene export
// it reads (docs/export.md), end to end through the CLI as a user runs them:
//   lsds export-scene -> the glTF holds the very triangles lsds casts (read back with assimp);
//   lsds generate --renderer cycles -> every truth layer byte-identical to the reference
//   renderer's, Cycles' own depth and object index passes agreeing with them (the figures in
//   provenance), an rgb of Cycles' own in the reference's units that shows every target, and
//   lsds validate --fail-on warning passing.
// The Cycles test is skipped, with its reason, when Blender is not installed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>

#include "generator/cycles/cycles_frame.h"
#include "generator/plan_source.h"
#include "generator/render/embree_scene.h"
#include "generator/scene/world.h"
#include "generator/scene/world_meshes.h"
#include "generator/scene_export/scene_export.h"
#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/process.h"
#include "tests/test_util.h"
#include "validators/cycles_agreement_check.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using testing::RunCommandLine;
using testing::RunLsds;
using testing::TempDir;

// The agreement rule on passes whose answer is known (no Blender needed): a 16 x 12 ground at
// 10 m seen by both renderers, with (a) a one-pixel leaf only Cycles' sample caught, (b) a 3 cm
// rim step that fell between lsds's pixel centre and Cycles' sample, (c) a 4 x 4 patch Cycles
// draws 1 % deeper than lsds: only (c) is a disagreement.
TEST(CyclesAgreement, CountsDisplacedGeometryNotSubPixelFeaturesOrSmallSteps) {
  const int w = 16, h = 12;
  gen::Film film = gen::Film::Make(w, h, 1, /*with_bundle=*/false);
  exr::FlatImage cycles(w, h);
  std::vector<float>& cycles_depth =
      cycles.AddChannel("ViewLayer.Depth.Z", exr::PixelType::kFloat).floats;
  std::vector<float>& cycles_index =
      cycles.AddChannel("ViewLayer.IndexOB.X", exr::PixelType::kFloat).floats;
  std::vector<float>& depth = film.flat.at("depth").Get("Z").floats;
  std::vector<uint32_t>& instance = film.flat.at("instanceid").Get("id").uints;
  for (size_t p = 0; p < depth.size(); ++p) {
    depth[p] = 10.f;
    cycles_depth[p] = 10.f;
    cycles_index[p] = gen::kTerrainPassIndex;
    instance[p] = 1;
  }
  cycles_depth[cycles.Index(3, 3)] = 8.f;   // (a) the leaf
  depth[cycles.Index(8, 2)] = 9.97f;        // (b) the rim at lsds's centre ...
  cycles_depth[cycles.Index(8, 2)] = 10.f;  // ... the tyre behind it, as the neighbours see
  for (int y = 6; y < 10; ++y)
    for (int x = 9; x < 13; ++x) cycles_depth[cycles.Index(x, y)] = 10.1f;  // (c)
  const TempDir dir;
  exr::WriteFlatExr(dir / "cycles.exr", cycles);
  const std::vector<gen::ExportedNode> nodes = {{"terrain", gen::kTerrainPassIndex, 1, 1}};
  const auto camera = PinholeCamera::FromHorizontalFov(w, h, 60);
  const gen::CyclesAgreement agreement =
      gen::CompareWithCycles(dir / "cycles.exr", film, nodes, camera, DepthKind::kPlanar, 0);
  EXPECT_EQ(agreement.id_mismatches, 0);
  // (c)'s inner 2 x 2 is smooth in both: 0.1 m beyond the 10 m lsds saw there and around.
  EXPECT_NEAR(agreement.max_relative_depth_error, 0.01, 1e-6);
  // Without (c), (a) and (b) leave no disagreement.
  for (int y = 6; y < 10; ++y)
    for (int x = 9; x < 13; ++x) cycles_depth[cycles.Index(x, y)] = 10.f;
  exr::WriteFlatExr(dir / "cycles.exr", cycles);
  EXPECT_EQ(gen::CompareWithCycles(dir / "cycles.exr", film, nodes, camera, DepthKind::kPlanar, 0)
                .max_relative_depth_error,
            0.0);
}

// A hilly field with two cars, a person and a gold cube under a morning sun, seen obliquely
// from two positions at 64 x 48.
constexpr const char* kScene =
    "LSCENE = ONE(S) ONE(DL) ONE(W) MANY(CAR, 2) ONE(MAN) ONE(BOX)\n"
    "S = skybox{color:blue}\n"
    "DL = light{elevation:40,azimuth:120,intensity:100000}\n"
    "W = terrain{size:[60,60],height:{perlin:{amplitude:1,frequency:0.05}},material:grassy}\n"
    "CAR = object{class:car,rotation:[0,0,[0,360]],position:{ON:W,within:[[-6,-6,-100],[6,6,"
    "100]]}}\n"
    "MAN = object{class:person,position:{ON:W,within:[[-3,-3,-100],[3,3,100]]}}\n"
    "BOX = object{class:cube,extent:[2,2,2],material:MetalGold,position:{ON:W,within:[[-5,-5,"
    "-100],[5,5,100]]}}\n";
constexpr const char* kCapture =
    "LCAP = ONE(CO) ONE(P)\n"
    "CO = camera{csettings:{fov:60,res:[64,48]},targets:[CAR,MAN,BOX]}\n"
    "P = path{waypoints:[{position:[-14,-14,12],look_at:[0,0,0]},"
    "{position:[-10,-16,13],look_at:[0,0,0]}]}\n";

struct Files {
  fs::path scene, capture;
};

Files WriteInputs(const TempDir& dir) {
  Files f{dir / "field.lscene", dir / "field.lcap"};
  std::ofstream(f.scene) << kScene;
  std::ofstream(f.capture) << kCapture;
  return f;
}

// A world point back from glTF's +Y-up frame.
Eigen::Vector3f WorldFromGltf(const aiVector3D& p) { return {p.x, -p.z, p.y}; }

// The triangles of the glb's mesh `name`, in world coordinates.
std::vector<std::array<Eigen::Vector3f, 3>> GlbTriangles(const aiScene& scene,
                                                         const std::string& name) {
  std::vector<std::array<Eigen::Vector3f, 3>> triangles;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[m];
    // A node's primitives (parts by albedo, docs/export.md) are assimp's meshes NAME-K.
    const std::string mesh_name = mesh.mName.C_Str();
    if (mesh_name != name && mesh_name.rfind(name + "-", 0) != 0) continue;
    for (unsigned t = 0; t < mesh.mNumFaces; ++t) {
      const aiFace& face = mesh.mFaces[t];
      triangles.push_back({WorldFromGltf(mesh.mVertices[face.mIndices[0]]),
                           WorldFromGltf(mesh.mVertices[face.mIndices[1]]),
                           WorldFromGltf(mesh.mVertices[face.mIndices[2]])});
    }
  }
  return triangles;
}

// Every triangle of `expected` is in the glb with bit-identical vertices, and no other: in
// order, but for a mesh with base-colour maps, whose primitives group its triangles by albedo.
void ExpectSameTriangles(const aiScene& scene,
                         const std::string& name,
                         const gen::TriangleMesh& expected) {
  auto triangles = GlbTriangles(scene, name);
  ASSERT_EQ(triangles.size(), expected.triangles.size()) << name;
  std::vector<std::array<Eigen::Vector3f, 3>> wanted;
  for (const Eigen::Vector3i& t : expected.triangles)
    wanted.push_back(
        {expected.positions[t[0]], expected.positions[t[1]], expected.positions[t[2]]});
  if (!expected.albedo_maps.empty()) {
    const auto before = [](const std::array<Eigen::Vector3f, 3>& a,
                           const std::array<Eigen::Vector3f, 3>& b) {
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k)
          if (a[c][k] != b[c][k]) return a[c][k] < b[c][k];
      return false;
    };
    std::sort(triangles.begin(), triangles.end(), before);
    std::sort(wanted.begin(), wanted.end(), before);
  }
  size_t different = 0;
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      if (triangles[t][c] != wanted[t][c]) ++different;
  EXPECT_EQ(different, 0u) << name << ": corners that moved in the export";
}

TEST(ExportScene, WritesTheTrianglesTheReferenceRendererCasts) {
  const TempDir dir;
  const Files in = WriteInputs(dir);
  const fs::path out = dir / "export";
  const auto run = RunLsds("export-scene " + in.scene.string() + " " + in.capture.string() +
                           " -o " + out.string() + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;

  const Plan plan = gen::PlanFromScene(in.scene.string(), in.capture.string(), 0);
  ASSERT_EQ(plan.frames.size(), 2u);
  const nlohmann::json index = nlohmann::json::parse(ReadFile(out / "scene.json"));
  EXPECT_EQ(index["format"], "lsds-scene-export");
  ASSERT_EQ(index["frames"].size(), 2u);

  // The ground: terrain and skirt exactly as Embree gets them.
  Assimp::Importer importer;
  const aiScene* ground = importer.ReadFile((out / "ground.glb").string(), 0);
  ASSERT_NE(ground, nullptr) << importer.GetErrorString();
  const gen::GroundMeshes expected_ground = gen::MakeGroundMeshes(plan.terrain);
  ExpectSameTriangles(*ground, "terrain", expected_ground.terrain);
  ExpectSameTriangles(*ground, "skirt", expected_ground.skirt);

  // Frame 1: each object's world-space mesh, and the frame's camera as planned.
  const gen::SceneAssets assets = gen::BuildSceneAssets(plan);
  const PlannedFrame& frame = plan.frames[1];
  const gen::WorldState world = gen::WorldAt(plan, frame);
  Assimp::Importer object_importer;
  const aiScene* objects = object_importer.ReadFile((out / "000001.glb").string(), 0);
  ASSERT_NE(objects, nullptr) << object_importer.GetErrorString();
  for (size_t i = 0; i < world.objects.size(); ++i)
    ExpectSameTriangles(
        *objects,
        "object_" + std::to_string(i),
        gen::ObjectMeshInWorld(assets.ShapeOf(i, world.objects[i].asset), world.objects[i]));
  const nlohmann::json description = nlohmann::json::parse(ReadFile(out / "000001.json"));
  EXPECT_EQ(description["camera"]["fx"].get<double>(), frame.camera.fx);
  EXPECT_EQ(description["camera"]["cx"].get<double>(), frame.camera.cx);
  const Eigen::Matrix3d r = frame.cam_from_world.rotation.toRotationMatrix();
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      EXPECT_EQ(description["camera"]["cam_from_world"]["rotation"][row][col].get<double>(),
                r(row, col));
  // Nodes: the terrain with its ids, one per object with its instance id; pass indices unique.
  std::map<int, std::string> passes;
  for (const auto& node : description["nodes"]) {
    const int pass = node["pass_index"].get<int>();
    if (pass > 0) {
      EXPECT_TRUE(passes.emplace(pass, node["name"]).second) << node.dump();
    }
  }
  EXPECT_EQ(passes.at(gen::kTerrainPassIndex), "terrain");
  EXPECT_EQ(passes.size(), 1 + world.objects.size());

  // An existing export is kept without --force.
  const auto again = RunLsds("export-scene " + in.scene.string() + " " + in.capture.string() +
                             " -o " + out.string() + " -q");
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.output.find("--force"), std::string::npos) << again.output;
}

TEST(RendererCycles, MissingBlenderIsAClearErrorNamingThePackage) {
  const TempDir dir;
  const Files in = WriteInputs(dir);
  const std::string args = " generate " + in.scene.string() + " " + in.capture.string() + " -o " +
                           (dir / "out").string() + " --renderer cycles -q";
  const auto no_path =
      RunCommandLine("env PATH=" + (dir / "empty").string() + " " + testing::LsdsBinary() + args);
  EXPECT_EQ(no_path.exit_code, 2) << no_path.output;
  EXPECT_NE(no_path.output.find("Debian package `blender`"), std::string::npos) << no_path.output;
  const auto bad_flag =
      RunCommandLine(testing::LsdsBinary() + args + " --blender " + (dir / "nope").string());
  EXPECT_EQ(bad_flag.exit_code, 2) << bad_flag.output;
  EXPECT_NE(bad_flag.output.find("--blender"), std::string::npos) << bad_flag.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

struct Image {
  exr::FlatImage rgb;
  std::vector<uint32_t> instance;
};

Image ReadFrame(const fs::path& root, const nlohmann::json& frame) {
  Image image;
  image.rgb = exr::ReadFlatExr(root / frame["files"]["rgb"].get<std::string>(), {"R", "G", "B"});
  image.instance = exr::ReadFlatExr(root / frame["files"]["instanceid"].get<std::string>(), {"id"})
                       .Get("id")
                       .uints;
  return image;
}

Eigen::Vector3d MeanColour(const exr::FlatImage& rgb, const std::vector<bool>& mask) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double n = 0;
  for (size_t p = 0; p < mask.size(); ++p) {
    if (!mask[p]) continue;
    sum += Eigen::Vector3d(rgb.Get("R").floats[p], rgb.Get("G").floats[p], rgb.Get("B").floats[p]);
    ++n;
  }
  return n > 0 ? Eigen::Vector3d(sum / n) : sum;
}

TEST(RendererCycles, RendersTheRgbWhileEveryTruthLayerStaysTheReferenceRenderers) {
  if (FindOnPath("blender").empty())
    GTEST_SKIP() << "Blender is not installed (Debian package `blender`; "
                    "scripts/install-deps.sh installs it)";
  const TempDir dir;
  const Files in = WriteInputs(dir);
  // The plan, with frame 1's principal point off centre and non-square pixels, so that the
  // camera conversion to Blender (shift, sensor fit, pixel aspect) is checked by the passes.
  const fs::path plan_path = dir / "plan.json";
  const auto planned = RunLsds("plan " + in.scene.string() + " " + in.capture.string() + " -o " +
                               plan_path.string() + " -q");
  ASSERT_EQ(planned.exit_code, 0) << planned.output;
  nlohmann::json plan = nlohmann::json::parse(ReadFile(plan_path));
  nlohmann::json& camera = plan["frames"][1]["camera"];
  camera["cx"] = camera["cx"].get<double>() + 4.5;
  camera["cy"] = camera["cy"].get<double>() - 3.25;
  camera["fy"] = camera["fy"].get<double>() * 1.08;
  WriteFileAtomic(plan_path, plan.dump());

  const fs::path reference = dir / "reference", cycles = dir / "cycles";
  const std::string common = " --plan " + plan_path.string() + " --spp 16";
  const auto ref_run = RunLsds("generate" + common + " -o " + reference.string() + " -q");
  ASSERT_EQ(ref_run.exit_code, 0) << ref_run.output;
  const auto cyc_run =
      RunLsds("generate" + common + " -o " + cycles.string() + " --renderer cycles");
  ASSERT_EQ(cyc_run.exit_code, 0) << cyc_run.output;
  std::cout << cyc_run.output;

  const nlohmann::json ref = nlohmann::json::parse(ReadFile(reference / "collection.json"));
  const nlohmann::json cyc = nlohmann::json::parse(ReadFile(cycles / "collection.json"));
  // The truth: collection.json's frames (objects, cameras) and every layer but rgb. Auto exposure
  // meters each renderer's own rgb: the same scene in the same photometric units meters within
  // an EV.
  nlohmann::json ref_frames = ref["frames"], cyc_frames = cyc["frames"];
  for (size_t k = 0; k < ref_frames.size(); ++k) {
    const double ev_ref = ref_frames[k]["exposure"]["ev100"].get<double>();
    const double ev_cyc = cyc_frames[k]["exposure"]["ev100"].get<double>();
    std::cout << "frame " << k << ": EV100 metered on the reference's rgb " << ev_ref
              << ", on Cycles' " << ev_cyc << "\n";
    EXPECT_NEAR(ev_cyc, ev_ref, 1.0) << "frame " << k;
    ref_frames[k].erase("exposure");
    cyc_frames[k].erase("exposure");
  }
  EXPECT_EQ(ref_frames, cyc_frames);
  size_t compared = 0;
  for (const auto& frame : ref["frames"]) {
    for (const auto& [layer, file] : frame["files"].items()) {
      if (layer == "rgb") continue;
      EXPECT_EQ(ReadFile(reference / file.get<std::string>()),
                ReadFile(cycles / file.get<std::string>()))
          << file;
      ++compared;
    }
  }
  EXPECT_GE(compared, 2u * 6);

  // Cycles' own depth and object index passes against lsds's layers.
  const nlohmann::json& agreement = cyc["provenance"]["render"]["cycles_agreement"];
  ASSERT_TRUE(agreement.is_object()) << cyc["provenance"].dump();
  EXPECT_EQ(agreement["frames"], 2);
  const double depth_error = agreement["max_relative_depth_error"].get<double>();
  const double id_share = agreement["max_id_mismatch_share"].get<double>();
  std::cout << "Cycles against lsds: max relative depth error " << depth_error << " (over "
            << agreement["depth_pixels"] << " of " << agreement["pixels"] << " pixels)"
            << ", max share of pixels whose id differs " << id_share << "\n";
  RecordProperty("max_relative_depth_error", std::to_string(depth_error));
  RecordProperty("max_id_mismatch_share", std::to_string(id_share));
  EXPECT_LE(depth_error, validate::kMaxCyclesRelativeDepthError);
  // The depth was compared on most pixels (all but silhouettes, grazing ground and sky).
  EXPECT_GT(agreement["depth_pixels"].get<double>(), 0.5 * agreement["pixels"].get<double>())
      << agreement.dump();
  EXPECT_LE(id_share, validate::kMaxCyclesIdMismatchShare);
  EXPECT_EQ(cyc["provenance"]["render"]["cycles"]["samples"], 16);

  // The rgb is Cycles' own, in the reference's units, and shows every target.
  for (size_t k = 0; k < ref["frames"].size(); ++k) {
    const Image a = ReadFrame(reference, ref["frames"][k]);
    const Image b = ReadFrame(cycles, cyc["frames"][k]);
    const std::vector<bool> all(a.instance.size(), true);
    const Eigen::Vector3d mean_ref = MeanColour(a.rgb, all), mean_cyc = MeanColour(b.rgb, all);
    double difference = 0;
    for (const char* c : {"R", "G", "B"})
      for (size_t p = 0; p < a.instance.size(); ++p)
        difference += std::abs(a.rgb.Get(c).floats[p] - b.rgb.Get(c).floats[p]);
    difference /= 3.0 * static_cast<double>(a.instance.size());
    std::cout << "frame " << k << ": mean rgb reference " << mean_ref.transpose() << ", Cycles "
              << mean_cyc.transpose() << ", mean |difference| " << difference << "\n";
    EXPECT_GT(difference, 0.02 * mean_ref.mean()) << "frame " << k << ": rgb not Cycles' own";
    const double ratio = mean_cyc.mean() / mean_ref.mean();
    EXPECT_GT(ratio, 0.5) << "frame " << k << ": not the reference's linear units";
    EXPECT_LT(ratio, 2.0) << "frame " << k << ": not the reference's linear units";
    // Background: the pixels of no target.
    std::vector<bool> background(a.instance.size(), true);
    for (const auto& object : ref["frames"][k]["objects"]) {
      const uint32_t id = object["instance_id"].get<uint32_t>();
      for (size_t p = 0; p < a.instance.size(); ++p)
        if (a.instance[p] == id) background[p] = false;
    }
    const Eigen::Vector3d mean_background = MeanColour(b.rgb, background);
    int checked = 0;
    for (const auto& object : ref["frames"][k]["objects"]) {
      if (object["visible_pixels"].get<int64_t>() < 4) continue;
      const uint32_t id = object["instance_id"].get<uint32_t>();
      std::vector<bool> mask(a.instance.size());
      for (size_t p = 0; p < a.instance.size(); ++p) mask[p] = a.instance[p] == id;
      const Eigen::Vector3d inside = MeanColour(b.rgb, mask);
      const double contrast = (inside - mean_background).cwiseAbs().sum() / mean_background.sum();
      std::cout << "  " << object["name"].get<std::string>() << ": " << object["visible_pixels"]
                << " px, mean " << inside.transpose() << ", contrast to the background " << contrast
                << "\n";
      EXPECT_GT(contrast, 0.05) << "frame " << k << " " << object["name"]
                                << ": not visible in Cycles' rgb";
      ++checked;
    }
    EXPECT_GE(checked, 2) << "frame " << k;
  }

  const auto validated = RunLsds("validate " + cycles.string() + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
}

// A flat field seen from 3 m up towards the horizon, under fixed exposure, so that the near
// ground is a few metres away and the far ground hundreds: `atmosphere` is the one line that
// differs between the clear and the foggy capture.
std::string FlatFieldScene(const std::string& atmosphere) {
  return "LSCENE = ONE(S) ONE(DL) ONE(W) ONE(A)\n"
         "S = skybox{color:blue}\n"
         "DL = light{elevation:40,azimuth:120,intensity:100000}\n"
         "W = terrain{size:[800,800],material:grassy}\n"
         "A = atmosphere{" +
         atmosphere + "}\n";
}
constexpr const char* kHorizonCapture =
    "LCAP = ONE(CO) ONE(P)\n"
    "CO = camera{csettings:{fov:60,res:[64,48],ev100:14}}\n"
    "P = path{waypoints:[{position:[0,0,3],look_at:[100,0,0]}]}\n";

struct FoggedFrame {
  exr::FlatImage rgb;
  std::vector<float> distance;  // the perspective depth layer: metres from the camera
  nlohmann::json collection;
};

FoggedFrame GenerateWithCycles(const TempDir& dir,
                               const std::string& name,
                               const std::string& atm) {
  const fs::path scene = dir / (name + ".lscene"), capture = dir / "horizon.lcap";
  std::ofstream(scene) << FlatFieldScene(atm);
  std::ofstream(capture) << kHorizonCapture;
  const fs::path out = dir / name;
  const auto run = RunLsds("generate " + scene.string() + " " + capture.string() + " -o " +
                           out.string() + " --renderer cycles --spp 16 --depth perspective -q");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  FoggedFrame f;
  f.collection = nlohmann::json::parse(ReadFile(out / "collection.json"));
  const nlohmann::json& frame = f.collection["frames"][0];
  f.rgb = exr::ReadFlatExr(out / frame["files"]["rgb"].get<std::string>(), {"R", "G", "B"});
  f.distance =
      exr::ReadFlatExr(out / frame["files"]["depth"].get<std::string>(), {"Z"}).Get("Z").floats;
  const auto validated = RunLsds("validate " + out.string() + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
  return f;
}

double Luminance(const exr::FlatImage& rgb, size_t p) {
  return 0.2126 * rgb.Get("R").floats[p] + 0.7152 * rgb.Get("G").floats[p] +
         0.0722 * rgb.Get("B").floats[p];
}

// Fog (docs/export.md, `atmosphere`): Cycles draws the capture's visibility as the reference
// renderer's Koschmieder fog. Against the clear render of the same frame and exposure, each ground
// pixel at distance d should be clear * t + fog * (1 - t), t = exp(-3.912 / visibility * d), with
// the fog's radiance from the export: far ground nears the fog's colour, near ground keeps its
// contrast, and the truth still agrees with Cycles' passes.
TEST(RendererCycles, DrawsTheCapturesFogAsTheReferenceRendererModelsIt) {
  if (FindOnPath("blender").empty())
    GTEST_SKIP() << "Blender is not installed (Debian package `blender`; "
                    "scripts/install-deps.sh installs it)";
  const TempDir dir;
  const FoggedFrame clear = GenerateWithCycles(dir, "clear", "fog:0");
  const FoggedFrame foggy = GenerateWithCycles(dir, "foggy", "visibility:300");
  ASSERT_EQ(clear.distance, foggy.distance);  // the same ground, the same truth

  // The export states the fog: its extinction and the radiance far surfaces take.
  const auto exported =
      RunLsds("export-scene " + (dir / "foggy.lscene").string() + " " +
              (dir / "horizon.lcap").string() + " -o " + (dir / "export").string() + " -q");
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  const nlohmann::json atmosphere =
      nlohmann::json::parse(ReadFile(dir / "export" / "000000.json"))["atmosphere"];
  const double extinction = atmosphere["extinction_per_m"].get<double>();
  EXPECT_NEAR(extinction, 3.912 / 300, 1e-12);
  const nlohmann::json& exposure = foggy.collection["frames"][0]["exposure"];
  ASSERT_EQ(exposure["mode"], "manual");
  ASSERT_EQ(exposure, clear.collection["frames"][0]["exposure"]);
  const double scale = exposure["scale"].get<double>();
  const std::vector<double> fog = atmosphere["fog_radiance"].get<std::vector<double>>();
  const double fog_luminance = scale * (0.2126 * fog[0] + 0.7152 * fog[1] + 0.0722 * fog[2]);
  ASSERT_GT(fog_luminance, 0);

  // Near (under 20 m) and far (over 150 m) ground: mean luminance measured and predicted, and
  // how far from the fog's luminance each is (its contrast to the fog).
  struct Band {
    double clear = 0, measured = 0, predicted = 0;
    int pixels = 0;
  };
  Band near, far;
  for (size_t p = 0; p < foggy.distance.size(); ++p) {
    const double d = foggy.distance[p];
    if (!std::isfinite(d) || (d >= 20 && d <= 150)) continue;
    Band& band = d < 20 ? near : far;
    const double t = std::exp(-extinction * d);
    band.clear += Luminance(clear.rgb, p);
    band.measured += Luminance(foggy.rgb, p);
    band.predicted += Luminance(clear.rgb, p) * t + fog_luminance * (1 - t);
    ++band.pixels;
  }
  ASSERT_GE(near.pixels, 100);
  ASSERT_GE(far.pixels, 30);
  for (Band* band : {&near, &far}) {
    const std::string name = band == &near ? "near" : "far";
    band->clear /= band->pixels, band->measured /= band->pixels, band->predicted /= band->pixels;
    std::cout << name << " ground (" << band->pixels << " px): clear " << band->clear
              << ", fog measured " << band->measured << ", predicted " << band->predicted
              << ", fog luminance " << fog_luminance << "\n";
    EXPECT_NEAR(band->measured, band->predicted, 0.05 * band->predicted) << name;
  }
  // The fog takes away most of the far ground's contrast to it and little of the near ground's.
  const double near_kept =
      std::abs(near.measured - fog_luminance) / std::abs(near.clear - fog_luminance);
  const double far_kept =
      std::abs(far.measured - fog_luminance) / std::abs(far.clear - fog_luminance);
  std::cout << "contrast to the fog kept: near " << near_kept << ", far " << far_kept << "\n";
  EXPECT_GT(near_kept, 0.75);
  // Far ground lit by the Perez sky's bright horizon (the exported sky image) can be as bright as
  // the fog already; only where it differs from the fog is there contrast for the fog to take.
  if (std::abs(far.clear - fog_luminance) > 0.2 * fog_luminance) {
    EXPECT_LT(far_kept, 0.25);
  } else {
    std::cout << "far ground's clear luminance within 20 % of the fog's: its contrast is not "
                 "measured (the band's fog model above is)\n";
  }

  const nlohmann::json& agreement = foggy.collection["provenance"]["render"]["cycles_agreement"];
  EXPECT_LE(agreement["max_relative_depth_error"].get<double>(),
            validate::kMaxCyclesRelativeDepthError);
  EXPECT_LE(agreement["max_id_mismatch_share"].get<double>(), validate::kMaxCyclesIdMismatchShare);
}

// Shards of a --renderer cycles run each check their own frames; lsds merge adds their counts up
// and keeps the largest figures, and the merged collection validates.
TEST(RendererCycles, ShardsMergeTheirAgreement) {
  if (FindOnPath("blender").empty())
    GTEST_SKIP() << "Blender is not installed (Debian package `blender`; "
                    "scripts/install-deps.sh installs it)";
  const TempDir dir;
  const Files in = WriteInputs(dir);
  const std::string common = " generate " + in.scene.string() + " " + in.capture.string() +
                             " --spp 4 --renderer cycles -q --shard ";
  std::vector<nlohmann::json> shards;
  for (const char* shard : {"0/2", "1/2"}) {
    const fs::path out = dir / (std::string("s") + shard[0]);
    const auto run = RunLsds(common + shard + " -o " + out.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    shards.push_back(nlohmann::json::parse(
        ReadFile(out / "collection.json"))["provenance"]["render"]["cycles_agreement"]);
    EXPECT_EQ(shards.back()["frames"], 1);
  }
  const fs::path merged = dir / "merged";
  const auto merge = RunLsds("merge " + (dir / "s0").string() + " " + (dir / "s1").string() +
                             " -o " + merged.string() + " -q");
  ASSERT_EQ(merge.exit_code, 0) << merge.output;
  const nlohmann::json agreement = nlohmann::json::parse(
      ReadFile(merged / "collection.json"))["provenance"]["render"]["cycles_agreement"];
  EXPECT_EQ(agreement["frames"], 2);
  EXPECT_EQ(agreement["pixels"].get<int64_t>(),
            shards[0]["pixels"].get<int64_t>() + shards[1]["pixels"].get<int64_t>());
  EXPECT_EQ(agreement["max_relative_depth_error"].get<double>(),
            std::max(shards[0]["max_relative_depth_error"].get<double>(),
                     shards[1]["max_relative_depth_error"].get<double>()));
  const auto validated = RunLsds("validate " + merged.string() + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
}

}  // namespace
}  // namespace lsds
