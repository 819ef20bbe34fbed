// Built-in assets and image textures (docs/generator.md, "Built-in classes"
// and "Image textures"): every built-in class fills its unit box, is
// deterministic per seed and renders into the id layers; a car keeps the size
// the plan asks for; a glTF and an OBJ asset with a checker texture show the
// checker's colours where the texture puts them.
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "generator/render/integrator.h"
#include "generator/render/truth.h"
#include "generator/scene/object_library.h"
#include "libs/util/error.h"
#include "tests/generator/test_plans.h"
#include "tests/test_util.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;
using testing::FlatPlan;
using testing::Nadir;

struct Rendered {
  Film film;
  std::vector<ObjectTruth> truth;
};

// `ground_detail` false: the terrain's smooth patterns alone, which a pixel's
// samples can share (RenderSettings::ground_detail).
Rendered Render(const Plan& plan,
                int spp = 1,
                bool shade_pixels_once = true,
                bool ground_detail = true) {
  static EmbreeDevice device;
  const SceneAssets assets = BuildSceneAssets(plan);
  const WorldState world = WorldAt(plan, plan.frames[0]);
  const RenderScene scene(device, plan, assets, world);
  RenderSettings settings;
  settings.sampler = {spp, 1.0, plan.seed};
  settings.shade_pixels_once = shade_pixels_once;
  settings.ground_detail = ground_detail;
  Rendered r{RenderFrame(scene, Sky(plan), plan.frames[0], PreviousView(), settings), {}};
  uint64_t rays = 0;
  r.truth = ComputeObjectTruth(scene, plan.frames[0], r.film, 0.0, &rays);
  return r;
}

const std::vector<float>& F(const Film& film, const char* layer, const char* channel) {
  return film.flat.at(layer).Get(channel).floats;
}
const std::vector<uint32_t>& Ids(const Film& film, const char* layer) {
  return film.flat.at(layer).Get("id").uints;
}

PlannedObject Object(const std::string& class_name,
                     uint32_t instance_id,
                     const Eigen::Vector3d& position,
                     const Eigen::Vector3d& extent) {
  PlannedObject o = testing::Box(class_name, instance_id, position, extent);
  o.class_name = class_name;
  return o;
}

TEST(BuiltinClasses, EveryClassFillsItsUnitBoxAndIsDeterministicPerSeed) {
  for (const BuiltinClass& c : BuiltinClassTable()) {
    SCOPED_TRACE(c.name);
    const ClassShape a = MakeClassShape(c.name, 11, "test");
    const ClassShape b = MakeClassShape(c.name, 11, "test");
    ASSERT_FALSE(a.mesh.empty());
    ASSERT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
    for (size_t i = 0; i < a.mesh.positions.size(); ++i)
      ASSERT_EQ(a.mesh.positions[i], b.mesh.positions[i]);
    Eigen::Vector3f lo = a.mesh.positions[0], hi = lo;
    for (const Eigen::Vector3f& p : a.mesh.positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    EXPECT_TRUE(lo.isApprox(Eigen::Vector3f::Constant(-0.5f), 1e-5f)) << lo.transpose();
    EXPECT_TRUE(hi.isApprox(Eigen::Vector3f::Constant(0.5f), 1e-5f)) << hi.transpose();
    for (const Eigen::Vector3i& t : a.mesh.triangles)
      for (int k = 0; k < 3; ++k) ASSERT_LT(t[k], static_cast<int>(a.mesh.positions.size()));
    EXPECT_EQ(a.default_extent, c.default_extent);
    EXPECT_GT(c.default_extent.minCoeff(), 0);
  }
  // The seeded classes vary with the seed.
  for (const char* name : {"rock", "tree", "person", "bush"}) {
    const ClassShape a = MakeClassShape(name, 1, "test"), b = MakeClassShape(name, 2, "test");
    EXPECT_TRUE(a.mesh.positions.size() != b.mesh.positions.size() ||
                a.mesh.positions != b.mesh.positions)
        << name;
  }
}

TEST(BuiltinClasses, IcosphereIsClosedAndWoundOutward) {
  const TriangleMesh sphere = MakeIcosphereMesh(2);
  EXPECT_EQ(sphere.positions.size(), 162u);  // 10 * 4^2 + 2
  EXPECT_EQ(sphere.triangles.size(), 320u);
  std::map<std::pair<int, int>, int> edges;  // each directed edge once: closed, consistent
  for (const Eigen::Vector3i& t : sphere.triangles) {
    const Eigen::Vector3f a = sphere.positions[t[0]], b = sphere.positions[t[1]],
                          c = sphere.positions[t[2]];
    EXPECT_GT((b - a).cross(c - a).dot(a + b + c), 0);
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u);
  }
  for (const Eigen::Vector3f& p : sphere.positions) EXPECT_NEAR(p.norm(), 0.5f, 1e-6f);
}

TEST(BuiltinClasses, PluralsAndSynonymsNameTheSameClass) {
  const std::map<std::string, std::string> spellings = {{"cars", "car"},
                                                        {"trucks", "truck"},
                                                        {"lorries", "truck"},
                                                        {"trees", "tree"},
                                                        {"crates", "crate"},
                                                        {"barrels", "barrel"},
                                                        {"rocks", "rock"},
                                                        {"humans", "person"},
                                                        {"people", "person"}};
  for (const auto& [alias, canonical] : spellings) {
    EXPECT_EQ(CanonicalClassName(alias), canonical);
    ASSERT_NE(FindBuiltinClass(alias), nullptr) << alias;
    EXPECT_EQ(FindBuiltinClass(alias)->name, canonical);
  }
}

// Each built-in at its default size on a grid, seen from above: every one is
// in the instance and class layers, and its tight box covers its footprint.
TEST(BuiltinClasses, EveryBuiltinRendersIntoTheIdLayers) {
  Plan plan = FlatPlan(384, 384, 60);
  const std::vector<BuiltinClass>& table = BuiltinClassTable();
  plan.classes = {{1, "ground"}};
  for (size_t i = 0; i < table.size(); ++i) {
    const BuiltinClass& c = table[i];
    const double x = -13.5 + 9.0 * static_cast<double>(i % 4);
    const double y = 13.5 - 9.0 * static_cast<double>(i / 4);
    const uint32_t class_id = static_cast<uint32_t>(10 + i);
    plan.classes.push_back({class_id, c.name});
    PlannedObject o = Object(
        c.name, static_cast<uint32_t>(1 + i), {x, y, c.default_extent.z() / 2}, c.default_extent);
    o.class_id = class_id;
    plan.objects.push_back(o);
  }
  plan.frames[0].cam_from_world = Nadir({0, 0, 40});
  const Rendered r = Render(plan);
  std::map<uint32_t, int> pixels;
  const auto& instance = Ids(r.film, "instanceid");
  const auto& class_layer = Ids(r.film, "classid");
  for (size_t p = 0; p < instance.size(); ++p) {
    if (instance[p] == 0 || instance[p] == 1000) continue;
    ++pixels[instance[p]];
    EXPECT_EQ(class_layer[p], 9 + instance[p]);
  }
  for (size_t i = 0; i < table.size(); ++i) {
    const Eigen::Vector3d& e = table[i].default_extent;
    // The footprint in pixels at the top's distance: at least a third of the
    // box's (shapes are not boxes), and one pixel at the least.
    const double px = plan.frames[0].camera.fx / (40 - e.z());
    const double footprint = e.x() * e.y() * px * px;
    EXPECT_GE(pixels[static_cast<uint32_t>(1 + i)], std::max(1.0, footprint / 3)) << table[i].name;
  }
  EXPECT_EQ(r.truth.size(), table.size());
}

// The paper's vehicle at the size the plan asks: the truth's 3D box is that
// size, and the rendered surface reaches the box on every side.
TEST(BuiltinClasses, CarKeepsTheSizeThePlanAsks) {
  const Eigen::Vector3d size(4, 1.8, 1.5);
  for (const char* view : {"top", "side"}) {
    SCOPED_TRACE(view);
    Plan plan = FlatPlan(320, 240, 30);
    plan.objects.push_back(Object("car", 1, {0, 0, size.z() / 2}, size));
    const bool top = std::string(view) == "top";
    plan.frames[0].cam_from_world =
        top ? Nadir({0, 0, 20}) : LookAt({0, -25, 0.75}, {0, 0, 0.75}, Eigen::Vector3d::UnitZ());
    const Rendered r = Render(plan);
    ASSERT_EQ(r.truth.size(), 1u);
    EXPECT_TRUE((2 * r.truth[0].obb->half_extents).isApprox(size, 1e-12))
        << r.truth[0].obb->half_extents.transpose();
    // The world positions of the car's pixels span its size (to a pixel).
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
    const auto& instance = Ids(r.film, "instanceid");
    for (size_t p = 0; p < instance.size(); ++p) {
      if (instance[p] != 1) continue;
      const Eigen::Vector3d w(F(r.film, "worldposition", "X")[p],
                              F(r.film, "worldposition", "Y")[p],
                              F(r.film, "worldposition", "Z")[p]);
      lo = lo.cwiseMin(w);
      hi = hi.cwiseMax(w);
    }
    const Eigen::Vector3d span = hi - lo;
    const double pixel = (top ? 20.0 : 26.0) / plan.frames[0].camera.fx;  // metres per pixel
    EXPECT_NEAR(span.x(), size.x(), 2 * pixel);
    if (top) {
      EXPECT_NEAR(span.y(), size.y(), 2 * pixel);
    } else {
      EXPECT_NEAR(span.z(), size.z(), 2 * pixel);
    }
    for (int a = 0; a < 3; ++a) {  // inside the box
      EXPECT_GE(lo[a], -size[a] / 2 + (a == 2 ? size.z() / 2 : 0) - 1e-3);
      EXPECT_LE(hi[a], size[a] / 2 + (a == 2 ? size.z() / 2 : 0) + 1e-3);
    }
  }
}

// A 2 x 2 checker, 8-bit sRGB, top-left and bottom-right `a`, the others `b`.
const std::array<unsigned char, 3> kRed = {200, 40, 30}, kBlue = {30, 60, 210};
void WriteChecker(const fs::path& png) {
  cv::Mat image(16, 16, CV_8UC3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const auto& c = ((x < 8) == (y < 8)) ? kRed : kBlue;
      image.at<cv::Vec3b>(y, x) = cv::Vec3b(c[2], c[1], c[0]);
    }
  ASSERT_TRUE(cv::imwrite(png.string(), image));
}

// A 2 m quad, y-up as glTF 2.0 requires, texture coordinates (0, 0) at the
// image's top-left (glTF's convention) on the corner that lands at world
// (-1, +1): the red quadrants are world (-x, +y) and (+x, -y). `embedded`:
// a binary .glb holding the PNG in its buffer, else quad.gltf + quad.bin +
// checker.png.
void WriteGltfQuad(const fs::path& dir, bool embedded = false) {
  WriteChecker(dir / "checker.png");
  const float positions[4][3] = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  const float uvs[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const uint16_t indices[8] = {0, 2, 1, 0, 3, 2, 0, 0};  // padded to 4 bytes
  std::string bin(reinterpret_cast<const char*>(positions), sizeof positions);
  bin.append(reinterpret_cast<const char*>(uvs), sizeof uvs);
  bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
  nlohmann::json views = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                          {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 32}},
                          {{"buffer", 0}, {"byteOffset", 80}, {"byteLength", 12}}};
  nlohmann::json image = {{"uri", "checker.png"}};
  if (embedded) {
    std::ifstream in(dir / "checker.png", std::ios::binary);
    const std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    views.push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", png.size()}});
    image = {{"bufferView", 3}, {"mimeType", "image/png"}};
    bin += png;
    while (bin.size() % 4) bin.push_back('\0');
  }
  nlohmann::json buffer = {{"byteLength", bin.size()}};
  if (!embedded) buffer["uri"] = "quad.bin";
  const nlohmann::json gltf = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}},
            {"indices", 2},
            {"material", 0}}}}}}},
      {"materials", {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}}},
      {"textures", {{{"source", 0}}}},
      {"images", {image}},
      {"buffers", {buffer}},
      {"bufferViews", views},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 4},
         {"type", "VEC3"},
         {"min", {-1, 0, -1}},
         {"max", {1, 0, 1}}},
        {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
        {{"bufferView", 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}}};
  if (!embedded) {
    std::ofstream(dir / "quad.bin", std::ios::binary) << bin;
    std::ofstream(dir / "quad.gltf") << gltf.dump(1);
    return;
  }
  fs::remove(dir / "checker.png");  // the .glb must not need it
  std::string json = gltf.dump();
  while (json.size() % 4) json.push_back(' ');
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const std::string glb = "glTF" + u32(2) +
                          u32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size())) +
                          u32(static_cast<uint32_t>(json.size())) + "JSON" + json +
                          u32(static_cast<uint32_t>(bin.size())) + std::string("BIN\0", 4) + bin;
  std::ofstream(dir / "quad.glb", std::ios::binary) << glb;
}

// The same quad as OBJ (z-up, OBJ's texture origin at the image's
// bottom-left) with its material's map_Kd.
void WriteObjQuad(const fs::path& dir) {
  WriteChecker(dir / "checker.png");
  std::ofstream(dir / "quad.mtl") << "newmtl checker\nKd 1 1 1\nmap_Kd checker.png\n";
  std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\n"
                                     "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                     "usemtl checker\nf 1/1 2/2 3/3 4/4\n";
}

// Chromaticity (r, g, b) / (r + g + b): what survives any grey lighting.
Eigen::Vector3d Chroma(const Eigen::Vector3d& rgb) { return rgb / rgb.sum(); }
Eigen::Vector3d LinearChroma(const std::array<unsigned char, 3>& c) {
  Eigen::Vector3d linear;
  for (int a = 0; a < 3; ++a) {
    const double v = c[a] / 255.0;
    linear[a] = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  }
  return Chroma(linear);
}

void ExpectCheckerRendered(const std::string& mesh) {
  Plan plan = FlatPlan(96, 96, 40);
  plan.sun.elevation_deg = 90;  // overhead: no shadow on the quad
  plan.objects.push_back(Object(mesh, 1, {0, 0, 0.5}, {2, 2, 1}));
  plan.objects.back().material = "fabric";  // matte: no sky reflection tints the colours
  plan.frames[0].cam_from_world = Nadir({0, 0, 6});
  const Rendered r = Render(plan);
  Eigen::Vector3d sum[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  int count[2] = {0, 0};
  const auto& instance = Ids(r.film, "instanceid");
  for (size_t p = 0; p < instance.size(); ++p) {
    if (instance[p] != 1) continue;
    const double x = F(r.film, "worldposition", "X")[p], y = F(r.film, "worldposition", "Y")[p];
    if (std::abs(x) < 0.15 || std::abs(y) < 0.15) continue;  // away from the checker's edges
    const int red = (x < 0) == (y > 0) ? 0 : 1;
    sum[red] += Eigen::Vector3d(
        F(r.film, "rgb", "R")[p], F(r.film, "rgb", "G")[p], F(r.film, "rgb", "B")[p]);
    ++count[red];
  }
  ASSERT_GT(count[0], 200);
  ASSERT_GT(count[1], 200);
  const Eigen::Vector3d red = Chroma(sum[0]), blue = Chroma(sum[1]);
  EXPECT_LT((red - LinearChroma(kRed)).cwiseAbs().maxCoeff(), 0.06) << red.transpose();
  EXPECT_LT((blue - LinearChroma(kBlue)).cwiseAbs().maxCoeff(), 0.06) << blue.transpose();
  EXPECT_GT(red.x() / red.z(), 5);  // the two colours, not a blend of them
  EXPECT_GT(blue.z() / blue.x(), 5);
  // The truth layers see the quad, not its texture: one class, one normal.
  for (size_t p = 0; p < instance.size(); ++p) {
    if (instance[p] == 1) {
      ASSERT_EQ(F(r.film, "normal", "Z")[p], 1.f);
    }
  }
}

TEST(ImageTextures, GltfBaseColourTextureRenders) {
  lsds::testing::TempDir dir;
  WriteGltfQuad(dir.path());
  ExpectCheckerRendered((dir.path() / "quad.gltf").string());
}

TEST(ImageTextures, GlbEmbeddedTextureRenders) {
  lsds::testing::TempDir dir;
  WriteGltfQuad(dir.path(), true);
  ASSERT_FALSE(fs::exists(dir.path() / "checker.png"));
  ExpectCheckerRendered((dir.path() / "quad.glb").string());
}

TEST(ImageTextures, ObjDiffuseMapRenders) {
  lsds::testing::TempDir dir;
  WriteObjQuad(dir.path());
  ExpectCheckerRendered((dir.path() / "quad.obj").string());
}

// An image texture changes within a pixel: its pixels are shaded at every
// sample, where the smooth grass around it is shaded once per pixel
// (RenderSettings::shade_pixels_once; in fog, whose depth varies across a
// pixel, that changes the grass's RGB).
TEST(ImageTextures, TexturedPixelsAreShadedAtEverySample) {
  lsds::testing::TempDir dir;
  WriteObjQuad(dir.path());
  Plan plan = FlatPlan(96, 96, 40);
  plan.terrain.material = "grassy";
  plan.sun.elevation_deg = 90;
  plan.fog_density = 0.01;
  plan.objects.push_back(Object((dir.path() / "quad.obj").string(), 1, {0, 0, 0.5}, {2, 2, 1}));
  plan.objects.back().material = "fabric";
  plan.frames[0].cam_from_world = Nadir({0, 0, 6});
  const Rendered once = Render(plan, 4, true, false);
  const Rendered per_sample = Render(plan, 4, false, false);
  const auto& instance = Ids(once.film, "instanceid");
  int quad = 0, ground_changed = 0;
  for (size_t p = 0; p < instance.size(); ++p) {
    for (const char* c : {"R", "G", "B"}) {
      const bool same = F(once.film, "rgb", c)[p] == F(per_sample.film, "rgb", c)[p];
      if (instance[p] == 1) {
        ASSERT_TRUE(same) << "pixel " << p;
      } else {
        ground_changed += !same;
      }
    }
    quad += instance[p] == 1;
  }
  EXPECT_GT(quad, 1000);
  EXPECT_GT(ground_changed, 100);
}

TEST(ImageTextures, MissingTextureImageIsNamed) {
  lsds::testing::TempDir dir;
  WriteGltfQuad(dir.path());
  fs::remove(dir.path() / "checker.png");
  try {
    MakeClassShape((dir.path() / "quad.gltf").string(), 1, "object 'Q'");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("checker.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("object 'Q'"), std::string::npos) << e.what();
  }
}

// From the command line: a textured glTF in LSCENE generates a collection that
// validates.
TEST(ImageTextures, TexturedAssetCollectionValidates) {
  lsds::testing::TempDir dir;
  WriteGltfQuad(dir.path());
  std::ofstream(dir.path() / "s.lscene")
      << "LSCENE = ONE(W) ONE(O) ONE(C)\nW = terrain{size:[40,40]}\n"
         "O = object{class:quad.gltf,extent:[2,2,0.01],"
         "position:{within:[[-0.1,-0.1,0.3],[0.1,0.1,0.31]]}}\n"
         "C = object{class:car,position:{ON:W,within:[[4,-1,-9],[6,1,9]]}}\n";
  std::ofstream(dir.path() / "c.lcap")
      << "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
         "CO = camera{csettings:{fov:60,res:[64,48],fps:1},targets:[O,C]}\n"
         "P = path{waypoints:[[0,0,12,0,-90,0],[1,0,12,0,-90,0]]}\n"
         "CL = collection{CO:{move:[P]}}\n";
  const std::string out = (dir.path() / "out").string();
  const std::string lsds = lsds::testing::LsdsBinary();
  const auto generated = lsds::testing::RunCommandLine(
      lsds + " generate " + (dir.path() / "s.lscene").string() + " " +
      (dir.path() / "c.lcap").string() + " -o " + out + " --spp 1 -q");
  ASSERT_EQ(generated.exit_code, 0) << generated.output;
  const auto validated =
      lsds::testing::RunCommandLine(lsds + " validate " + out + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
}

}  // namespace
}  // namespace lsds::gen
