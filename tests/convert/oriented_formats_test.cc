// dota and yolo-obb on a synthetic collection with rotated boxes, a box cut
// by the border, a one-pixel box and a frame without objects: every label
// file is read back with the consumers' own rules (obb_consumers.h: DOTA
// devkit, MMRotate, Ultralytics) and every oriented box is checked against the
// instance mask it stands for (it covers every pixel; its area is that of
// OpenCV's minimum-area rectangle of the mask, an independent implementation).
#include <cmath>
#include <set>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "converters/dota/dota_converter.h"
#include "converters/loss_report.h"
#include "converters/yolo/yolo_converter.h"
#include "libs/collection/rig.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "tests/build_paths.h"
#include "tests/convert/convert_test_util.h"
#include "tests/convert/obb_checks.h"

namespace lsds::testing {
namespace {

constexpr uint32_t kSinglePixel = 7;
constexpr uint32_t kBorder = 8;

// DefaultSpec (boxes at yaw 0, 30 and -20 degrees), the crate class renamed
// "Small Crate" (DOTA writes "small-crate"), a box covering one pixel, a box
// at yaw 35 cut by the left border, and a fifth frame over empty ground.
synth::Spec ObbSpec() {
  synth::Spec spec = synth::DefaultSpec();
  spec.classes[2].name = "Small Crate";
  const PinholeCamera camera =
      PinholeCamera::FromHorizontalFov(spec.width, spec.height, spec.hfov_deg);
  const Rigid3d world_from_cam = spec.cam_from_world[0].Inverse();
  const Eigen::Vector3d ray = camera.CamFromImage({40.5, 20.5});
  synth::Box pixel;
  pixel.class_id = 3, pixel.instance_id = kSinglePixel, pixel.name = "crate#1";
  pixel.center =
      world_from_cam * Eigen::Vector3d(ray / ray.z() * 19.0) - Eigen::Vector3d(0, 0, 0.05);
  pixel.half_extents = {0.05, 0.05, 0.05};
  synth::Box border;
  border.class_id = 2, border.instance_id = kBorder, border.name = "box#2";
  const Eigen::Vector3d edge = camera.CamFromImage({0.5, 24.5});
  border.center =
      world_from_cam * Eigen::Vector3d(edge / edge.z() * 19.0) - Eigen::Vector3d(0, 0, 0.5);
  border.half_extents = {1.5, 0.8, 0.5};
  border.yaw_deg = 35;
  spec.boxes.push_back(pixel);
  spec.boxes.push_back(border);
  spec.cam_from_world.push_back(synth::NadirCamFromWorld({200.0, 0.0, 20.0}));
  return spec;
}

class OrientedFormatsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    synth::WriteCollection(Collection(), ObbSpec());
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path Collection() { return dir_->path() / "collection"; }
  static fs::path Out(const std::string& name) { return dir_->path() / name; }
  static TempDir* dir_;
};
TempDir* OrientedFormatsTest::dir_ = nullptr;

TEST_F(OrientedFormatsTest, PreconditionsOfTheTestScene) {
  const std::vector<Frame> frames = Frames(Collection());
  ASSERT_EQ(frames.size(), 5u);
  bool single = false, border = false;
  for (const ObjectTruth& o : frames[0].objects) {
    if (o.instance_id == kSinglePixel) single = o.visible_pixels == 1;
    if (o.instance_id == kBorder) border = o.bbox && o.bbox->x0 == 0 && o.in_frame < 1;
  }
  EXPECT_TRUE(single);
  EXPECT_TRUE(border);
  EXPECT_TRUE(Visible(Collection(), frames[4]).empty());
}

TEST_F(OrientedFormatsTest, DotaLinesPassTheDevkitAndMmrotateAndCoverTheMasks) {
  const fs::path out = Out("dota");
  const convert::ConvertResult result = convert::Convert(Options(Collection(), out, {"dota"}));
  const DotaFindings found = CheckDota(Collection(), out);
  EXPECT_GT(found.lines, 8);
  EXPECT_GE(found.under_size, 1);  // the one-pixel box
  EXPECT_GE(found.empty_images, 1);
  EXPECT_EQ(result.loss.Total(convert::loss::kDotaUnderMinSize), found.under_size);
  EXPECT_EQ(result.loss.Count(convert::loss::kDotaEmptyImages, convert::loss::kImages),
            found.empty_images);
}

TEST_F(OrientedFormatsTest, DotaHeaderIsOptInAndStopsMmrotate) {
  const fs::path out = Out("dota-header");
  convert::ConvertOptions options = Options(Collection(), out, {"dota"});
  options.dota_header = true;
  options.dota_min_size = 0;  // every object written
  options.dota_difficult_below = 0;
  options.dota_difficult_size = 0;  // nothing difficult
  convert::Convert(options);
  const Frame frame = Frames(Collection())[0];
  const std::string text = ReadText(out / "labelTxt/train" / (FrameFileStem(frame) + ".txt"));
  const std::vector<std::string> lines = Lines(text);
  ASSERT_GE(lines.size(), 3u);
  EXPECT_EQ(lines[0], "imagesource:lsds");
  EXPECT_EQ(lines[1], "gsd:null");  // the synthetic collection's metadata has no GSD
  std::string error;
  EXPECT_EQ(DevkitParse(text, &error).size(), lines.size() - 2);  // the devkit skips them
  EXPECT_EQ(error, "");
  EXPECT_TRUE(MmrotateLoad(text, {"box", "small-crate"}).crashed);
  EXPECT_EQ(lines.size() - 2, Visible(Collection(), frame).size());
  for (size_t i = 2; i < lines.size(); ++i) EXPECT_EQ(SplitSpace(lines[i])[9], "0");
}

TEST_F(OrientedFormatsTest, DotaRefusesJpegImagesAndClassesThatCollide) {
  convert::ConvertOptions options = Options(Collection(), Out("dota-jpg"), {"dota"});
  options.images = "jpg";
  EXPECT_THROW(convert::Convert(options), Error);
  options.images = "none";
  options.classes = "box=Small Car,3=small car";
  EXPECT_THROW(convert::Convert(options), Error);
  EXPECT_FALSE(fs::exists(Out("dota-jpg")));
  EXPECT_EQ(convert::DotaClassName("Small\tCar 2"), "small-car-2");
}

TEST_F(OrientedFormatsTest, YoloObbPassesUltralyticsChecksAndCoversTheMasks) {
  const fs::path out = Out("yolo-obb");
  const convert::ConvertResult result = convert::Convert(Options(Collection(), out, {"yolo-obb"}));
  const int border_lines = CheckYoloObb(Collection(), out);
  EXPECT_GE(border_lines, 1);  // the box cut by the left border
  EXPECT_LE(result.loss.Total(convert::loss::kObbClipped), border_lines);
}

// A square at 45 degrees reaching out of a 10 x 10 image: the line is cut to
// the image (every value in [0, 1]) and says so; a box inside is unchanged.
TEST(YoloObbLine, ClipsARotatedBoxToTheImage) {
  OrientedBox2d box;
  box.corners = {Eigen::Vector2d(1, 3), {3, 5}, {1, 7}, {-1, 5}};
  bool clipped = false;
  const std::string line = convert::YoloObbLine(4, box, 10, 10, &clipped);
  EXPECT_TRUE(clipped) << line;
  const std::vector<std::string> t = SplitWhitespace(line);
  ASSERT_EQ(t.size(), 9u) << line;
  EXPECT_EQ(t[0], "4");
  for (size_t i = 1; i < t.size(); ++i) {
    const double v = *PyFloat(t[i]);
    EXPECT_TRUE(v >= 0 && v <= 1) << line;
  }
  EXPECT_FALSE(UltralyticsVerify(line, 5).dropped);
  box.corners = {Eigen::Vector2d(2, 3), {4, 5}, {2, 7}, {0, 5}};
  EXPECT_EQ(convert::YoloObbLine(1, box, 10, 10, &clipped),
            "1 0.200000 0.300000 0.400000 0.500000 0.200000 0.700000 0.000000 0.500000\n");
  EXPECT_FALSE(clipped);
}

}  // namespace
}  // namespace lsds::testing
