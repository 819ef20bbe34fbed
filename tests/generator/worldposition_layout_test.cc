// The residual worldposition layout (docs/format.md "Worldposition layouts"):
// lossless against the float layout bit for bit, read by the one reader for
// both, and, end to end, collections generated in either layout validate and
// back-project to byte-identical clouds; a corrupt residual file is an error
// naming the file.
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "libs/collection/collection_reader.h"
#include "libs/collection/float_residual.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/exr_info.h"
#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "tests/build_paths.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using exr::FlatImage;
using exr::PixelType;
using testing::RunLsds;
using testing::TempDir;

// How many values of channels X, Y, Z differ in their bits (NaN, -0 included).
size_t DifferingBits(const FlatImage& a, const FlatImage& b) {
  size_t differ = 0;
  for (const char* axis : {"X", "Y", "Z"}) {
    const std::vector<float>& va = a.Get(axis).floats;
    const std::vector<float>& vb = b.Get(axis).floats;
    EXPECT_EQ(va.size(), vb.size()) << axis;
    for (size_t i = 0; i < std::min(va.size(), vb.size()); ++i)
      differ += FloatBits(va[i]) != FloatBits(vb[i]);
  }
  return differ;
}

// A tilted (non-nadir) camera over a 16x12 image, perspective depth.
WorldPositionPrediction TiltedPrediction() {
  WorldPositionPrediction input;
  input.width = 16;
  input.height = 12;
  input.depth_kind = DepthKind::kPerspective;
  input.camera.intrinsics = PinholeCamera::FromHorizontalFov(16, 12, 60);
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()).toRotationMatrix() *
      Eigen::AngleAxisd(2.9, Eigen::Vector3d(0.2, 0.1, 1).normalized()).toRotationMatrix();
  input.camera.cam_from_world_rotation = r;
  input.camera.cam_from_world_translation = -(r * Eigen::Vector3d(12.5, -30.25, 80));
  input.depth.resize(16 * 12);
  for (size_t p = 0; p < input.depth.size(); ++p) input.depth[p] = 50.0f + 0.37f * p;
  input.depth[3] = std::numeric_limits<float>::infinity();  // sky
  input.depth[4] = std::numeric_limits<float>::quiet_NaN();
  return input;
}

TEST(WorldPositionLayout, ResidualReadsBackExactlyTheFloats) {
  TempDir dir;
  const WorldPositionPrediction input = TiltedPrediction();
  // The truth: the prediction moved by a few ulps, plus values no prediction
  // is near (a NaN, -0, -inf, a far point, the sky's +inf).
  FlatImage truth = PredictWorldPosition(input);
  std::mt19937 rng(7);
  for (const char* axis : {"X", "Y", "Z"}) {
    for (float& v : truth.Get(axis).floats) {
      if (std::isfinite(v)) v = std::nextafter(v, static_cast<float>(rng() % 2 ? 1e30 : -1e30));
    }
  }
  truth.Get("X").floats[5] = std::numeric_limits<float>::quiet_NaN();
  truth.Get("Y").floats[6] = -0.0f;
  truth.Get("Z").floats[7] = -std::numeric_limits<float>::infinity();
  truth.Get("Z").floats[8] = 3e38f;
  exr::WriteOptions zip;
  WriteWorldPositionExr(dir / "r.exr", truth, FlatLayout::kResidual, &input, "depth", zip);

  const exr::ExrInfo info = exr::ReadExrInfo(dir / "r.exr");
  EXPECT_EQ(info.attributes.at(kWorldPositionLayoutAttribute), "residual");
  EXPECT_EQ(info.attributes.at(kWorldPositionDepthAttribute), "depth");
  ASSERT_NE(info.Find("dX"), nullptr);
  EXPECT_EQ(info.Find("dX")->type, PixelType::kUint);
  EXPECT_EQ(info.Find("X"), nullptr);
  const std::vector<exr::ChannelSpec> readable = ReadableWorldPositionChannels(info);
  ASSERT_EQ(readable.size(), 3u);
  EXPECT_EQ(readable[0].name, "X");
  EXPECT_EQ(readable[0].type, PixelType::kFloat);
  // The sky's residual is 0: +inf predicted where the depth is not finite.
  const FlatImage stored = exr::ReadFlatExr(dir / "r.exr");
  EXPECT_EQ(stored.Get("dY").uints[3], 0u);
  EXPECT_EQ(stored.Get("dY").uints[4], 0u);

  std::string asked;
  const FlatImage back =
      ReadWorldPositionExr(dir / "r.exr", {}, [&](const std::string& depth_layer) {
        asked = depth_layer;
        return input;
      });
  EXPECT_EQ(asked, "depth");
  EXPECT_EQ(DifferingBits(back, truth), 0u);
  // A subset in the order asked.
  const FlatImage z =
      ReadWorldPositionExr(dir / "r.exr", {"Z"}, [&](const std::string&) { return input; });
  ASSERT_EQ(z.channels().size(), 1u);
  EXPECT_EQ(FloatBits(z.Get("Z").floats[8]), FloatBits(3e38f));

  // The float layout writes the floats as they are, the reader passes them on.
  WriteWorldPositionExr(dir / "f.exr", truth, FlatLayout::kFloat, nullptr, "", zip);
  EXPECT_EQ(exr::ReadExrInfo(dir / "f.exr").attributes.count(kWorldPositionLayoutAttribute), 0u);
  EXPECT_EQ(DifferingBits(ReadWorldPositionExr(dir / "f.exr", {}, nullptr), truth), 0u);
}

void ExpectErrorNaming(const std::function<void()>& read,
                       const std::string& file,
                       const std::string& words) {
  try {
    read();
    FAIL() << "expected an error about " << words;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(WorldPositionLayout, CorruptResidualFilesAreErrorsNamingTheFile) {
  TempDir dir;
  const WorldPositionPrediction input = TiltedPrediction();
  const auto predict = [&](const std::string&) { return input; };
  exr::WriteOptions residual;
  residual.attributes = {{kWorldPositionLayoutAttribute, "residual"},
                         {kWorldPositionDepthAttribute, "depth"}};
  FlatImage wrong_type(16, 12);
  wrong_type.AddChannel("dX", PixelType::kFloat);
  wrong_type.AddChannel("dY", PixelType::kUint);
  wrong_type.AddChannel("dZ", PixelType::kUint);
  exr::WriteFlatExr(dir / "wrong_type.exr", wrong_type, residual);
  ExpectErrorNaming([&] { ReadWorldPositionExr(dir / "wrong_type.exr", {}, predict); },
                    "wrong_type.exr",
                    "'dX' is float, expected uint");

  FlatImage missing(16, 12);
  missing.AddChannel("dX", PixelType::kUint);
  missing.AddChannel("dY", PixelType::kUint);
  exr::WriteFlatExr(dir / "missing.exr", missing, residual);
  ExpectErrorNaming([&] { ReadWorldPositionExr(dir / "missing.exr", {}, predict); },
                    "missing.exr",
                    "no channel 'dZ'");

  residual.attributes.erase(kWorldPositionDepthAttribute);
  missing.AddChannel("dZ", PixelType::kUint);
  exr::WriteFlatExr(dir / "no_depth.exr", missing, residual);
  ExpectErrorNaming([&] { ReadWorldPositionExr(dir / "no_depth.exr", {}, predict); },
                    "no_depth.exr",
                    kWorldPositionDepthAttribute);

  WorldPositionPrediction small = input;
  small.width = 8;
  small.depth.resize(8 * 12);
  WriteWorldPositionExr(
      dir / "size.exr", PredictWorldPosition(input), FlatLayout::kResidual, &input, "depth", {});
  ExpectErrorNaming(
      [&] {
        ReadWorldPositionExr(dir / "size.exr", {}, [&](const std::string&) { return small; });
      },
      "size.exr",
      "is 16x12 but its depth layer 'depth' is 8x12");
}

// --- End to end, the way a user meets it. ---

// Generates `source` twice (float and residual layout, same seed) and checks:
// the layer tables say which layout; every decoded worldposition value is
// bit-identical; `lsds validate --fail-on warning` passes on both; backproject
// clouds are byte-identical; the residual files are smaller.
void ExpectLayoutsAgree(const TempDir& dir, const std::string& source) {
  const fs::path f = dir / "float", r = dir / "residual";
  const std::string common = source + " --seed 4 --quiet -o ";
  auto g = RunLsds("generate " + common + f.string());  // float: the default
  ASSERT_EQ(g.exit_code, 0) << g.output;
  g = RunLsds("generate --worldposition-layout residual " + common + r.string());
  ASSERT_EQ(g.exit_code, 0) << g.output;
  for (const fs::path& root : {f, r}) {
    const auto v = RunLsds("validate " + root.string() + " --fail-on warning");
    EXPECT_EQ(v.exit_code, 0) << root << "\n" << v.output;
    const auto b = RunLsds("backproject " + root.string() + " --fuse -o " + root.string() + ".ply");
    EXPECT_EQ(b.exit_code, 0) << b.output;
    const auto c = RunLsds("backproject " + root.string() + " --check");
    EXPECT_EQ(c.exit_code, 0) << c.output;
  }
  EXPECT_EQ(ReadFile(f.string() + ".ply"), ReadFile(r.string() + ".ply"));
  // export-layers decodes too: the same .npy bytes from both.
  for (const fs::path& root : {f, r}) {
    const auto e = RunLsds("export-layers " + root.string() + " --layers worldposition -o " +
                           root.string() + "_npy");
    ASSERT_EQ(e.exit_code, 0) << e.output;
  }
  for (const auto& entry : fs::directory_iterator(f.string() + "_npy/worldposition")) {
    const fs::path other = r.string() + "_npy/worldposition/" + entry.path().filename().string();
    EXPECT_EQ(ReadFile(entry.path()), ReadFile(other)) << other;
  }
  EXPECT_GT(ReadFile(f.string() + ".ply").size(), 1000u);

  const CollectionReader rf(f), rr(r);
  EXPECT_EQ(rf.header().FindLayerBySemantic("worldposition")->flat_layout, FlatLayout::kFloat);
  EXPECT_EQ(rr.header().FindLayerBySemantic("worldposition")->flat_layout, FlatLayout::kResidual);
  std::vector<Frame> frames;
  rf.ForEachFrame([&](const Frame& frame) { frames.push_back(frame); });
  std::vector<Frame> residual_frames;
  rr.ForEachFrame([&](const Frame& frame) { residual_frames.push_back(frame); });
  ASSERT_EQ(frames.size(), residual_frames.size());
  ASSERT_GE(frames.size(), 2u);
  uintmax_t float_bytes = 0, residual_bytes = 0;
  size_t finite = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const fs::path fp = rf.LayerPath(frames[k], "worldposition");
    const fs::path rp = rr.LayerPath(residual_frames[k], "worldposition");
    EXPECT_EQ(exr::ReadExrInfo(rp).attributes.at(kWorldPositionLayoutAttribute), "residual");
    EXPECT_NE(exr::ReadExrInfo(rp).Find("dX"), nullptr);
    const FlatImage a = rf.ReadFlatLayer(frames[k], "worldposition", {"X", "Y", "Z"});
    const FlatImage b = rr.ReadFlatLayer(residual_frames[k], "worldposition", {"X", "Y", "Z"});
    EXPECT_EQ(DifferingBits(a, b), 0u) << fp;
    // The float file is what an EXR tool reads: the same values again.
    EXPECT_EQ(DifferingBits(exr::ReadFlatExr(fp), b), 0u) << fp;
    for (float v : a.Get("X").floats) finite += std::isfinite(v) ? 1 : 0;
    float_bytes += fs::file_size(fp);
    residual_bytes += fs::file_size(rp);
  }
  EXPECT_GT(finite, 0u);
  EXPECT_LT(residual_bytes, float_bytes * 3 / 4);
}

TEST(WorldPositionLayout, GeneratedDemoLayoutsAgree) {
  TempDir dir;
  ExpectLayoutsAgree(dir, "--demo --demo-size 64x48 --demo-frames 3");
}

// A nadir and an oblique rig camera (non-nadir pose), perspective depth.
TEST(WorldPositionLayout, GeneratedObliqueRigPerspectiveLayoutsAgree) {
  TempDir dir;
  std::ofstream(dir / "rig.lcap")
      << "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
         "CO = camera{csettings:{fov:60,res:[48,32],fps:1},"
         "rig:{nadir:{},oblique:{attitude:[0,30,0],csettings:{fov:50,res:[40,30]}}}}\n"
         "P = path{waypoints:{points:[[-10,0,45],[0,0,45]],speed:10}}\n"
         "CL = collection{CO:{move:[P]}}\n";
  ExpectLayoutsAgree(dir,
                     ::lsds::testing::ExamplesDir() + "/time_of_day_movers.lscene " +
                         (dir / "rig.lcap").string() + " --depth perspective");
}

// A residual file broken on disk: `lsds validate` reports it at the file, and
// readers (backproject) fail naming it.
TEST(WorldPositionLayout, ValidateLocatesACorruptResidualFile) {
  TempDir dir;
  const fs::path root = dir / "c";
  auto g = RunLsds(
      "generate --demo --demo-size 32x24 --demo-frames 2 --seed 1 --compact "
      "--quiet -o " +
      root.string());
  ASSERT_EQ(g.exit_code, 0) << g.output;
  const CollectionReader reader(root);
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& frame) { frames.push_back(frame); });
  const fs::path path = reader.LayerPath(frames.at(1), "worldposition");
  const std::string file = fs::relative(path, root).string();
  exr::ExrInfo info = exr::ReadExrInfo(path);
  FlatImage stored = exr::ReadFlatExr(path);
  // dZ as FLOAT, as a tool that "fixes" the types might write it.
  FlatImage broken(stored.width(), stored.height());
  broken.AddChannel("dX", PixelType::kUint).uints = stored.Get("dX").uints;
  broken.AddChannel("dY", PixelType::kUint).uints = stored.Get("dY").uints;
  broken.AddChannel("dZ", PixelType::kFloat);
  exr::WriteOptions options;
  options.attributes = info.attributes;
  exr::WriteFlatExr(path, broken, options);
  auto v = RunLsds("validate " + root.string());
  EXPECT_EQ(v.exit_code, 1) << v.output;
  EXPECT_NE(v.output.find(file), std::string::npos) << v.output;
  EXPECT_NE(v.output.find("channel 'Z'"), std::string::npos) << v.output;
  auto b = RunLsds("backproject " + root.string() + " --check");
  EXPECT_NE(b.exit_code, 0) << b.output;
  EXPECT_NE(b.output.find(file), std::string::npos) << b.output;
  EXPECT_NE(b.output.find("'dZ' is float, expected uint"), std::string::npos) << b.output;

  // Missing a channel.
  broken = FlatImage(stored.width(), stored.height());
  broken.AddChannel("dX", PixelType::kUint).uints = stored.Get("dX").uints;
  broken.AddChannel("dZ", PixelType::kUint).uints = stored.Get("dZ").uints;
  exr::WriteFlatExr(path, broken, options);
  v = RunLsds("validate " + root.string());
  EXPECT_EQ(v.exit_code, 1) << v.output;
  EXPECT_NE(v.output.find(file), std::string::npos) << v.output;
  EXPECT_NE(v.output.find("no channel 'Y'"), std::string::npos) << v.output;

  // Float values where the table says residual: read right, reported.
  exr::WriteFlatExr(
      path, PredictWorldPosition(PredictionOfFrame(root, reader.header(), frames.at(1), "depth")));
  v = RunLsds("validate " + root.string());
  EXPECT_EQ(v.exit_code, 1) << v.output;
  EXPECT_NE(v.output.find("stored in the float layout but layer 'worldposition' declares "
                          "layout 'residual'"),
            std::string::npos)
      << v.output;
}

}  // namespace
}  // namespace lsds
