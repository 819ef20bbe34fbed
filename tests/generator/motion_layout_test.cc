// The residual motion layout (docs/format.md "Motion layouts"): lossless
// against the float layout bit for bit (NaN included), read by the one reader
// for both; a shot's first frame predicts NaN everywhere; end to end,
// collections generated in either layout validate and decode to the same
// motion, and the residual files are a fraction of the floats.
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "libs/collection/collection_reader.h"
#include "libs/collection/float_residual.h"
#include "libs/collection/motion_layout.h"
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

// How many values of channels X, Y differ in their bits (NaN, -0 included).
size_t DifferingBits(const FlatImage& a, const FlatImage& b) {
  size_t differ = 0;
  for (const char* axis : {"X", "Y"}) {
    const std::vector<float>& va = a.Get(axis).floats;
    const std::vector<float>& vb = b.Get(axis).floats;
    EXPECT_EQ(va.size(), vb.size()) << axis;
    for (size_t i = 0; i < std::min(va.size(), vb.size()); ++i)
      differ += FloatBits(va[i]) != FloatBits(vb[i]);
  }
  return differ;
}

CameraTruth LookingDownFrom(const Eigen::Vector3d& eye, int w, int h) {
  CameraTruth camera;
  camera.intrinsics = PinholeCamera::FromHorizontalFov(w, h, 60);
  // x right, y down (south), z down: a nadir camera.
  camera.cam_from_world_rotation << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  camera.cam_from_world_translation = -(camera.cam_from_world_rotation * eye);
  return camera;
}

// A nadir camera 50 m over flat ground at z = 0, planar depth, a sky pixel.
WorldPositionPrediction GroundPrediction(int w, int h) {
  WorldPositionPrediction input;
  input.width = w;
  input.height = h;
  input.depth_kind = DepthKind::kPlanar;
  input.camera = LookingDownFrom({0, 0, 50}, w, h);
  input.depth.assign(static_cast<size_t>(w) * h, 50.0f);
  input.depth[2] = std::numeric_limits<float>::infinity();
  return input;
}

TEST(MotionLayout, PredictionIsTheCameraMotionOfAStaticWorld) {
  const WorldPositionPrediction input = GroundPrediction(16, 12);
  // The camera moved 1 m east since the previous frame: a ground point seen now at
  // pixel u was seen at u + fx / 50 pixels then.
  const CameraTruth previous = LookingDownFrom({-1, 0, 50}, 16, 12);
  const FlatImage m = PredictMotion(input, previous);
  const double fx = input.camera.intrinsics.fx;
  const size_t p = 5 * 16 + 7;
  EXPECT_NEAR(m.Get("X").floats[p], 0.5 + 0.5 * (-fx / 50) / 16, 1e-6);
  EXPECT_NEAR(m.Get("Y").floats[p], 0.5, 1e-7);
  // The sky (a direction) does not move with a translation.
  EXPECT_NEAR(m.Get("X").floats[2], 0.5, 1e-7);
  // A point the previous camera saw outside its image: NaN in both.
  const size_t left_edge = 5 * 16;
  EXPECT_TRUE(std::isnan(
      PredictMotion(input, LookingDownFrom({-40, 0, 50}, 16, 12)).Get("Y").floats[left_edge + 15]));
  // No previous camera (a shot's first frame): NaN everywhere.
  const FlatImage none = PredictMotion(input, std::nullopt);
  for (const char* axis : {"X", "Y"}) {
    for (float v : none.Get(axis).floats) EXPECT_TRUE(std::isnan(v));
  }
}

TEST(MotionLayout, ResidualReadsBackExactlyTheFloats) {
  TempDir dir;
  const WorldPositionPrediction input = GroundPrediction(16, 12);
  const CameraTruth previous = LookingDownFrom({-1, 0.5, 50}, 16, 12);
  FlatImage truth = PredictMotion(input, previous);
  std::mt19937 rng(3);
  for (const char* axis : {"X", "Y"}) {
    for (float& v : truth.Get(axis).floats) {
      if (std::isfinite(v)) v = std::nextafter(v, static_cast<float>(rng() % 2 ? 2 : -2));
    }
  }
  // A moving object, a disocclusion (NaN), -0 and a value far outside [0, 1].
  truth.Get("X").floats[20] = 0.9f;
  truth.Get("X").floats[21] = truth.Get("Y").floats[21] = std::numeric_limits<float>::quiet_NaN();
  truth.Get("Y").floats[22] = -0.0f;
  truth.Get("Y").floats[23] = 17.5f;
  WriteMotionExr(dir / "r.exr", truth, FlatLayout::kResidual, &input, previous, "depth", {});
  const exr::ExrInfo info = exr::ReadExrInfo(dir / "r.exr");
  EXPECT_EQ(info.attributes.at(kMotionLayoutAttribute), "residual");
  EXPECT_EQ(info.attributes.at(kMotionDepthAttribute), "depth");
  EXPECT_TRUE(IsResidualMotion(info));
  const std::vector<exr::ChannelSpec> readable = ReadableMotionChannels(info);
  ASSERT_EQ(readable.size(), 2u);
  EXPECT_EQ(readable[0].name, "X");
  EXPECT_EQ(readable[0].type, PixelType::kFloat);
  std::string asked;
  const FlatImage back = ReadMotionExr(dir / "r.exr", {}, [&](const std::string& depth) {
    asked = depth;
    return input;
  });
  EXPECT_EQ(asked, "depth");
  EXPECT_EQ(DifferingBits(back, truth), 0u);

  // A shot's first frame: all NaN, stored as all-zero residuals.
  FlatImage first = PredictMotion(input, std::nullopt);
  WriteMotionExr(dir / "s.exr", first, FlatLayout::kResidual, &input, std::nullopt, "depth", {});
  EXPECT_EQ(exr::ReadExrInfo(dir / "s.exr").attributes.at(kMotionPreviousCameraAttribute), "none");
  const FlatImage stored = exr::ReadFlatExr(dir / "s.exr");
  for (uint32_t d : stored.Get("dX").uints) EXPECT_EQ(d, 0u);
  EXPECT_EQ(DifferingBits(
                ReadMotionExr(dir / "s.exr", {}, [&](const std::string&) { return input; }), first),
            0u);
}

TEST(MotionLayout, BadPreviousCameraIsAnErrorNamingTheFileAndAttribute) {
  TempDir dir;
  const WorldPositionPrediction input = GroundPrediction(8, 6);
  const CameraTruth previous = LookingDownFrom({-1, 0, 50}, 8, 6);
  WriteMotionExr(dir / "good.exr",
                 PredictMotion(input, previous),
                 FlatLayout::kResidual,
                 &input,
                 previous,
                 "depth",
                 {});
  const exr::ExrInfo info = exr::ReadExrInfo(dir / "good.exr");
  const FlatImage stored = exr::ReadFlatExr(dir / "good.exr");
  for (const std::string& value : {std::string(), std::string("8 6 1 2 3"), std::string("n/a")}) {
    exr::WriteOptions options;
    options.attributes = info.attributes;
    if (value.empty()) {
      options.attributes.erase(kMotionPreviousCameraAttribute);
    } else {
      options.attributes[kMotionPreviousCameraAttribute] = value;
    }
    exr::WriteFlatExr(dir / "bad.exr", stored, options);
    try {
      ReadMotionExr(dir / "bad.exr", {}, [&](const std::string&) { return input; });
      FAIL() << "expected an error for '" << value << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("bad.exr"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(kMotionPreviousCameraAttribute), std::string::npos)
          << e.what();
    }
  }
}

// --- End to end, the way a user meets it. ---

// Generates `source` with float (the default) and residual motion, same seed:
// both validate with --fail-on warning, every decoded motion value is
// bit-identical, export-layers writes the same .npy bytes, and the residual
// files of frames with motion are under a quarter of the floats.
void ExpectLayoutsAgree(const TempDir& dir, const std::string& source) {
  const fs::path f = dir / "float", r = dir / "residual";
  const std::string common = source + " --seed 4 --quiet -o ";
  auto g = RunLsds("generate " + common + f.string());  // float: the default
  ASSERT_EQ(g.exit_code, 0) << g.output;
  g = RunLsds("generate --motion-layout residual " + common + r.string());
  ASSERT_EQ(g.exit_code, 0) << g.output;
  for (const fs::path& root : {f, r}) {
    const auto v = RunLsds("validate " + root.string() + " --fail-on warning");
    EXPECT_EQ(v.exit_code, 0) << root << "\n" << v.output;
    const auto e =
        RunLsds("export-layers " + root.string() + " --layers motion -o " + root.string() + "_npy");
    ASSERT_EQ(e.exit_code, 0) << e.output;
  }
  size_t exported = 0;
  for (const auto& entry : fs::directory_iterator(f.string() + "_npy/motion")) {
    const fs::path other = r.string() + "_npy/motion/" + entry.path().filename().string();
    EXPECT_EQ(ReadFile(entry.path()), ReadFile(other)) << other;
    ++exported;
  }
  EXPECT_GT(exported, 0u);

  const CollectionReader rf(f), rr(r);
  EXPECT_EQ(rf.header().FindLayerBySemantic("motion")->flat_layout, FlatLayout::kFloat);
  EXPECT_EQ(rr.header().FindLayerBySemantic("motion")->flat_layout, FlatLayout::kResidual);
  std::vector<Frame> frames, residual_frames;
  rf.ForEachFrame([&](const Frame& frame) { frames.push_back(frame); });
  rr.ForEachFrame([&](const Frame& frame) { residual_frames.push_back(frame); });
  ASSERT_EQ(frames.size(), residual_frames.size());
  uintmax_t float_bytes = 0, residual_bytes = 0;
  size_t finite = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const fs::path fp = rf.LayerPath(frames[k], "motion");
    const fs::path rp = rr.LayerPath(residual_frames[k], "motion");
    EXPECT_TRUE(IsResidualMotion(exr::ReadExrInfo(rp))) << rp;
    const FlatImage a = rf.ReadFlatLayer(frames[k], "motion", {"X", "Y"});
    const FlatImage b = rr.ReadFlatLayer(residual_frames[k], "motion", {"X", "Y"});
    EXPECT_EQ(DifferingBits(a, b), 0u) << fp;
    EXPECT_EQ(DifferingBits(exr::ReadFlatExr(fp), b), 0u) << fp;
    size_t frame_finite = 0;
    for (float v : a.Get("X").floats) frame_finite += std::isfinite(v) ? 1 : 0;
    finite += frame_finite;
    if (frame_finite > 0) {
      float_bytes += fs::file_size(fp);
      residual_bytes += fs::file_size(rp);
    }
  }
  EXPECT_GT(finite, 0u);
  EXPECT_LT(residual_bytes, float_bytes / 4);
}

TEST(MotionLayout, GeneratedDemoLayoutsAgree) {
  TempDir dir;
  ExpectLayoutsAgree(dir, "--demo --demo-size 96x64 --demo-frames 3");
}

// A rig (motion per camera, against the same camera one step earlier), moving
// objects, perspective depth.
TEST(MotionLayout, GeneratedRigWithMoversLayoutsAgree) {
  TempDir dir;
  std::ofstream(dir / "rig.lcap")
      << "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
         "CO = camera{csettings:{fov:60,res:[48,32],fps:1},"
         "rig:{nadir:{},oblique:{attitude:[0,30,0],csettings:{fov:50,res:[40,30]}}}}\n"
         "P = path{waypoints:{points:[[-10,0,45],[0,0,45]],speed:5}}\n"
         "CL = collection{CO:{move:[P]}}\n";
  ExpectLayoutsAgree(dir,
                     ::lsds::testing::ExamplesDir() + "/time_of_day_movers.lscene " +
                         (dir / "rig.lcap").string() + " --depth perspective");
}

// The table says residual but the file holds floats: read right, reported.
TEST(MotionLayout, ValidateReportsAFloatFileDeclaredResidual) {
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
  const FlatImage motion = reader.ReadFlatLayer(frames.at(1), "motion", {"X", "Y"});
  exr::WriteFlatExr(reader.LayerPath(frames.at(1), "motion"), motion);
  const auto v = RunLsds("validate " + root.string());
  EXPECT_EQ(v.exit_code, 1) << v.output;
  EXPECT_NE(v.output.find("stored in the float layout but layer 'motion' declares layout "
                          "'residual'"),
            std::string::npos)
      << v.output;
}

}  // namespace
}  // namespace lsds
