// The truth drawn on an image lies where the collection says it is: boxes on
// the pixels just inside their pixel-edge bounds, outlines on the mask's
// boundary pixels.
#include <set>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "report/draw.h"
#include "synth/synthetic_collection.h"

namespace lsds::report {
namespace {

using Pixel = std::pair<int, int>;  // (x, y)

std::set<Pixel> Painted(const cv::Mat& image) {
  std::set<Pixel> out;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      if (image.at<cv::Vec3b>(y, x) != cv::Vec3b(0, 0, 0)) out.insert({x, y});
    }
  }
  return out;
}

// The pixels of the first and last row and column of a pixel-edge box,
// computed from its edges (COCO's rule: pixel (i, j) is inside when x0 <= i <
// x1 and y0 <= j < y1).
std::set<Pixel> BorderPixels(const Box2d& box) {
  std::set<Pixel> out;
  const int x0 = static_cast<int>(box.x0), x1 = static_cast<int>(box.x1);
  const int y0 = static_cast<int>(box.y0), y1 = static_cast<int>(box.y1);
  for (int x = x0; x < x1; ++x) out.insert({x, y0}), out.insert({x, y1 - 1});
  for (int y = y0; y < y1; ++y) out.insert({x0, y}), out.insert({x1 - 1, y});
  return out;
}

TEST(Draw, BoxOfAKnownObjectLiesOnItsPixelEdgeBox) {
  // One 2 m box straight under a nadir camera at 20 m: its top face is a
  // square of side 2 fx / 18 px around the image centre (tests/libs/
  // synth_test.cc derives the same box analytically).
  synth::Spec spec = synth::DefaultSpec();
  synth::Box box;
  box.class_id = 2, box.instance_id = 1, box.name = "box#0";
  box.center = {0, 0, 1}, box.half_extents = {1, 1, 1};
  spec.boxes = {box};
  spec.cam_from_world = {synth::NadirCamFromWorld({0, 0, 20})};
  const synth::RenderedFrame frame = synth::RenderFrame(spec, 0);
  ASSERT_EQ(frame.truth.objects.size(), 1u);
  const Box2d truth = *frame.truth.objects[0].bbox;
  const PinholeCamera camera =
      PinholeCamera::FromHorizontalFov(spec.width, spec.height, spec.hfov_deg);
  const double half = camera.fx / 18.0;
  // The pixels whose centres fall inside the projected square.
  EXPECT_EQ(truth.x0, std::ceil(camera.cx - half - 0.5));
  EXPECT_EQ(truth.x1, std::floor(camera.cx + half - 0.5) + 1);

  cv::Mat image(spec.height, spec.width, CV_8UC3, cv::Scalar(0, 0, 0));
  DrawBox(&image, truth, 1.0, cv::Vec3b(255, 255, 255));
  EXPECT_EQ(Painted(image), BorderPixels(truth));
}

TEST(Draw, AnnotationsPaintExactlyTheBoxesOfEveryVisibleObject) {
  const synth::Spec spec = synth::DefaultSpec();
  CollectionHeader header;
  header.classes = spec.classes;
  for (int f = 0; f < static_cast<int>(spec.cam_from_world.size()); ++f) {
    const synth::RenderedFrame frame = synth::RenderFrame(spec, f);
    cv::Mat image(spec.height, spec.width, CV_8UC3, cv::Scalar(0, 0, 0));
    AnnotateOptions options;
    options.outlines = false, options.labels = false;
    DrawAnnotations(&image, header, frame.truth, nullptr, options);
    std::set<Pixel> expected;
    int visible = 0;
    for (const ObjectTruth& object : frame.truth.objects) {
      if (object.visible_pixels == 0) continue;
      ++visible;
      const std::set<Pixel> border = BorderPixels(*object.bbox);
      expected.insert(border.begin(), border.end());
    }
    EXPECT_GT(visible, 0);
    EXPECT_EQ(Painted(image), expected) << "frame " << f;
  }
}

TEST(Draw, OutlinesLieOnTheBoundaryOfTheInstanceMask) {
  const synth::Spec spec = synth::DefaultSpec();
  CollectionHeader header;
  header.classes = spec.classes;
  const synth::RenderedFrame frame = synth::RenderFrame(spec, 1);
  const exr::FlatImage& ids = frame.flat.at("instanceid");
  cv::Mat image(spec.height, spec.width, CV_8UC3, cv::Scalar(0, 0, 0));
  AnnotateOptions options;
  options.boxes = false, options.labels = false;
  DrawAnnotations(&image, header, frame.truth, &ids, options);
  const auto id_at = [&](int x, int y) -> uint32_t {
    if (x < 0 || y < 0 || x >= spec.width || y >= spec.height) return 0;
    return ids.Get("id").uints[ids.Index(x, y)];
  };
  std::set<Pixel> boundary;  // object pixels with a 4-neighbour of another id
  for (const ObjectTruth& object : frame.truth.objects) {
    for (int y = 0; y < spec.height; ++y) {
      for (int x = 0; x < spec.width; ++x) {
        const uint32_t id = id_at(x, y);
        if (id != object.instance_id) continue;
        if (id_at(x - 1, y) != id || id_at(x + 1, y) != id || id_at(x, y - 1) != id ||
            id_at(x, y + 1) != id) {
          boundary.insert({x, y});
        }
      }
    }
  }
  const std::set<Pixel> painted = Painted(image);
  ASSERT_FALSE(painted.empty());
  for (const Pixel& p : painted) {
    EXPECT_TRUE(boundary.count(p)) << "(" << p.first << ", " << p.second << ")";
    // In the colour of the instance it outlines.
    const uint32_t id = id_at(p.first, p.second);
    EXPECT_EQ(image.at<cv::Vec3b>(p.second, p.first), IdColor(id));
  }
}

TEST(Draw, ScaledBoxesRoundToTheNearestPixelEdge) {
  const cv::Size size(50, 40);
  EXPECT_EQ(PixelRect({10, 20, 30, 24}, 0.5, size), cv::Rect(5, 10, 10, 2));
  // Never thinner than a pixel, clipped to the image.
  EXPECT_EQ(PixelRect({10, 20, 11, 21}, 0.25, size), cv::Rect(3, 5, 1, 1));
  EXPECT_EQ(PixelRect({90, 70, 120, 100}, 0.5, size), cv::Rect(45, 35, 5, 5));
  EXPECT_TRUE(PixelRect({200, 200, 210, 210}, 0.5, size).empty());
}

TEST(Draw, IdColoursAreStableAndDistinct) {
  EXPECT_EQ(IdColor(0), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(IdColor(7), IdColor(7));
  std::set<std::tuple<int, int, int>> colours;
  for (uint32_t id = 1; id <= 64; ++id) {
    const cv::Vec3b c = IdColor(id);
    colours.insert({c[0], c[1], c[2]});
  }
  EXPECT_EQ(colours.size(), 64u);
}

}  // namespace
}  // namespace lsds::report
