// The image textures of loaded assets in the scene export and in Blender Cycles (docs/export.md,
// "Textures"), end to end as a user meets them:
//   lsds export-scene SCENE CAPTURE -> an object whose OBJ material has a map_Kd gets the map in
//   the export's textures/ folder (the source's very pixels), referenced from its node's `parts`,
//   and texture coordinates in its glTF;
//   lsds generate --renderer cycles -> Cycles' rgb shows the map's colours where the object's
//   instance mask is, in the quadrants the reference renderer shows them.
// The fixture, a 16 x 16 red/blue checker on the top of a box, is written by the test (the OBJ's
// own text below; no third-party file). The Cycles test is skipped, with its reason, when Blender
// is not installed.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/process.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using testing::RunLsds;
using testing::TempDir;

// 8-bit sRGB: the image's top-left and bottom-right quadrants red, the others blue.
constexpr std::array<unsigned char, 3> kRed = {200, 40, 30}, kBlue = {30, 60, 210};

cv::Mat Checker() {
  cv::Mat image(16, 16, CV_8UC3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const auto& c = ((x < 8) == (y < 8)) ? kRed : kBlue;
      image.at<cv::Vec3b>(y, x) = cv::Vec3b(c[2], c[1], c[0]);
    }
  return image;
}

// A unit box (z up) whose top face carries the whole checker, texture origin (OBJ's: the image's
// bottom-left) at its (-x, -y) corner: red on top at world (-x, +y) and (+x, -y). The sides
// take the texture's corner texel.
void WriteTexturedBox(const fs::path& dir, const std::string& map = "checker.png") {
  ASSERT_TRUE(cv::imwrite((dir / "checker.png").string(), Checker()));
  std::ofstream(dir / "box.mtl") << "newmtl checker\nKd 1 1 1\nmap_Kd " << map << "\n";
  std::ofstream(dir / "box.obj") << "mtllib box.mtl\n"
                                    "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
                                    "v -0.5 -0.5 1\nv 0.5 -0.5 1\nv 0.5 0.5 1\nv -0.5 0.5 1\n"
                                    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                    "usemtl checker\n"
                                    "f 5/1 6/2 7/3 8/4\n"  // top
                                    "f 1/1 4/1 3/1 2/1\n"  // bottom
                                    "f 1/1 2/1 6/1 5/1\nf 2/1 3/1 7/1 6/1\n"
                                    "f 3/1 4/1 8/1 7/1\nf 4/1 1/1 5/1 8/1\n";
}

// The box on a flat field, the sun overhead, seen from 8 m straight down.
struct Inputs {
  fs::path scene, capture;
};
Inputs WriteInputs(const fs::path& dir, const std::string& map = "checker.png") {
  WriteTexturedBox(dir, map);
  Inputs in{dir / "box.lscene", dir / "nadir.lcap"};
  std::ofstream(in.scene) << "LSCENE = ONE(S) ONE(DL) ONE(W) ONE(B)\n"
                             "S = skybox{color:blue}\n"
                             "DL = light{elevation:89,azimuth:0,intensity:100000}\n"
                             "W = terrain{size:[40,40],material:grassy}\n"
                             "B = object{class:\"box.obj\",extent:[4,4,0.5],material:fabric,"
                             "position:{ON:W,within:[[-0.01,-0.01,-9],[0.01,0.01,9]]}}\n";
  std::ofstream(in.capture) << "LCAP = ONE(CO) ONE(P)\n"
                               "CO = camera{csettings:{fov:60,res:[64,64]},targets:[B]}\n"
                               "P = path{point:{position:[0,0,8]}}\n";
  return in;
}

TEST(ExportScene, WritesLoadedAssetsTexturesAndReferencesThem) {
  const TempDir dir;
  const Inputs in = WriteInputs(dir.path());
  // Two frames: the map is written once.
  std::ofstream(dir / "two.lcap") << "LCAP = ONE(CO) ONE(P)\n"
                                     "CO = camera{csettings:{fov:60,res:[64,64]},targets:[B]}\n"
                                     "P = path{waypoints:[{position:[0,-1,8],look_at:[0,0,0]},"
                                     "{position:[1,-1,8],look_at:[0,0,0]}]}\n";
  const fs::path out = dir / "export";
  const auto run = RunLsds("export-scene " + in.scene.string() + " " + (dir / "two.lcap").string() +
                           " -o " + out.string() + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json frame = nlohmann::json::parse(ReadFile(out / "000000.json"));
  EXPECT_EQ(frame["format_version"], "1.2");
  const nlohmann::json* box = nullptr;
  for (const nlohmann::json& node : frame["nodes"])
    if (node.value("object", "") == "B#1") box = &node;
  ASSERT_NE(box, nullptr) << frame["nodes"].dump();
  // Every triangle has the map: one part, the map's file.
  ASSERT_TRUE(box->contains("parts")) << box->dump();
  ASSERT_EQ((*box)["parts"].size(), 1u) << box->dump();
  const std::string file = (*box)["parts"][0]["albedo_map"].get<std::string>();
  EXPECT_EQ(file, "textures/texture_0.png");
  // The source's very pixels: an 8-bit sRGB map goes out as it came in.
  const cv::Mat exported = cv::imread((out / file).string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(exported.empty()) << out / file;
  const cv::Mat source = Checker();
  ASSERT_EQ(exported.type(), source.type());
  EXPECT_EQ(cv::countNonZero(exported.reshape(1) != source.reshape(1)), 0);
  // The terrain has no map: no parts.
  EXPECT_FALSE(frame["nodes"][0].contains("parts"));
  // The glTF carries texture coordinates (glTF's attribute name is in its JSON chunk).
  const std::string glb = ReadFile(out / "000000.glb");
  EXPECT_NE(glb.find("TEXCOORD_0"), std::string::npos);
  EXPECT_NE(glb.find("object_0_part0"), std::string::npos);  // the part's glTF material
  const nlohmann::json frame1 = nlohmann::json::parse(ReadFile(out / "000001.json"));
  EXPECT_EQ(frame1["nodes"].back()["parts"][0]["albedo_map"], file);
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "textures"), fs::directory_iterator()), 1);
}

// A 16-bit map is more than 8-bit sRGB can hold: it goes out as the linear float texels the
// reference renderer samples (generator/scene/texture.cc: 16-bit values are sRGB-encoded).
TEST(ExportScene, WritesHighBitDepthMapsAsLinearExr) {
  const TempDir dir;
  cv::Mat deep(4, 4, CV_16UC3, cv::Scalar(1000, 30000, 65535));  // B, G, R
  ASSERT_TRUE(cv::imwrite((dir / "deep.png").string(), deep));
  const Inputs in = WriteInputs(dir.path(), "deep.png");
  const fs::path out = dir / "export";
  const auto run = RunLsds("export-scene " + in.scene.string() + " " + in.capture.string() +
                           " -o " + out.string() + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json frame = nlohmann::json::parse(ReadFile(out / "000000.json"));
  const std::string file = frame["nodes"].back()["parts"][0]["albedo_map"].get<std::string>();
  ASSERT_EQ(file, "textures/texture_0.exr");
  const exr::FlatImage map = exr::ReadFlatExr(out / file, {"R", "G", "B"});
  ASSERT_EQ(map.width(), 4);
  const auto linear = [](double encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
  };
  EXPECT_NEAR(map.Get("R").floats[5], 1.0, 1e-6);
  EXPECT_NEAR(map.Get("G").floats[5], linear(30000 / 65535.0), 1e-6);
  EXPECT_NEAR(map.Get("B").floats[5], linear(1000 / 65535.0), 1e-6);
}

// Mean linear RGB of the box's top in the red and the blue quadrants of its checker.
struct Quadrants {
  Eigen::Vector3d red = Eigen::Vector3d::Zero(), blue = Eigen::Vector3d::Zero();
  int red_pixels = 0, blue_pixels = 0;
};
Quadrants MeanByQuadrant(const fs::path& root, const nlohmann::json& frame, uint32_t instance) {
  const auto file = [&](const char* layer) {
    return root / frame["files"][layer].get<std::string>();
  };
  const exr::FlatImage rgb = exr::ReadFlatExr(file("rgb"), {"R", "G", "B"});
  const std::vector<uint32_t> ids = exr::ReadFlatExr(file("instanceid"), {"id"}).Get("id").uints;
  const exr::FlatImage world = exr::ReadFlatExr(file("worldposition"), {"X", "Y", "Z"});
  Quadrants q;
  for (size_t p = 0; p < ids.size(); ++p) {
    if (ids[p] != instance) continue;
    const double x = world.Get("X").floats[p], y = world.Get("Y").floats[p];
    if (std::abs(x) < 0.3 || std::abs(y) < 0.3 || std::abs(x) > 1.7 || std::abs(y) > 1.7)
      continue;  // away from the checker's and the top's edges
    const Eigen::Vector3d c(rgb.Get("R").floats[p], rgb.Get("G").floats[p], rgb.Get("B").floats[p]);
    if ((x < 0) == (y > 0)) {
      q.red += c, ++q.red_pixels;
    } else {
      q.blue += c, ++q.blue_pixels;
    }
  }
  return q;
}

TEST(RendererCycles, DrawsLoadedAssetsTexturesWhereTheirMaskIs) {
  if (FindOnPath("blender").empty())
    GTEST_SKIP() << "Blender is not installed (Debian package `blender`; "
                    "scripts/install-deps.sh installs it)";
  const TempDir dir;
  const Inputs in = WriteInputs(dir.path());
  const std::string inputs = in.scene.string() + " " + in.capture.string() + " --spp 4 -q";
  const fs::path reference = dir / "reference", cycles = dir / "cycles";
  const auto ref_run = RunLsds("generate " + inputs + " -o " + reference.string());
  ASSERT_EQ(ref_run.exit_code, 0) << ref_run.output;
  const auto cyc_run =
      RunLsds("generate " + inputs + " -o " + cycles.string() + " --renderer cycles");
  ASSERT_EQ(cyc_run.exit_code, 0) << cyc_run.output;
  const nlohmann::json ref = nlohmann::json::parse(ReadFile(reference / "collection.json"));
  const nlohmann::json cyc = nlohmann::json::parse(ReadFile(cycles / "collection.json"));
  const uint32_t instance = ref["frames"][0]["objects"][0]["instance_id"].get<uint32_t>();
  std::vector<Eigen::Vector3d> chroma;  // red's, blue's; the reference's, then Cycles'
  for (const auto& [name, root, frame] : {std::make_tuple("reference", reference, ref["frames"][0]),
                                          std::make_tuple("Cycles", cycles, cyc["frames"][0])}) {
    const Quadrants q = MeanByQuadrant(root, frame, instance);
    ASSERT_GT(q.red_pixels, 100) << name;
    ASSERT_GT(q.blue_pixels, 100) << name;
    const Eigen::Vector3d red = q.red / q.red_pixels, blue = q.blue / q.blue_pixels;
    std::cout << name << ": red quadrants " << red.transpose() << ", blue quadrants "
              << blue.transpose() << "\n";
    // The checker's colours (linear red 0.58 : 0.02 : 0.01, blue 0.01 : 0.05 : 0.64) under a
    // grey sun and a bluish sky: each quadrant's own channel leads by far.
    EXPECT_GT(red.x(), 5 * red.z()) << name;
    EXPECT_GT(blue.z(), 5 * blue.x()) << name;
    chroma.push_back(red / red.sum());
    chroma.push_back(blue / blue.sum());
  }
  // The same colours as the reference renderer's (each renderer meters its own exposure, so
  // chromaticities): 0.004 apart at most measured.
  EXPECT_LT((chroma[0] - chroma[2]).cwiseAbs().maxCoeff(), 0.02);
  EXPECT_LT((chroma[1] - chroma[3]).cwiseAbs().maxCoeff(), 0.02);
}

}  // namespace
}  // namespace lsds
