// The synthetic builder's layers against analytic answers computed here,
// independently.
#include <cmath>

#include <gtest/gtest.h>

#include "synth/synthetic_collection.h"

namespace lsds::synth {
namespace {

Spec OneBoxUnderCamera() {
  Spec spec = DefaultSpec();
  Box box;
  box.class_id = 2, box.instance_id = 1, box.name = "box#0";
  box.center = {0, 0, 1}, box.half_extents = {1, 1, 1};
  spec.boxes = {box};
  spec.cam_from_world = {NadirCamFromWorld({0, 0, 20}), NadirCamFromWorld({1, 0, 20})};
  return spec;
}

TEST(Synth, NadirCameraOverFlatGround) {
  const Spec spec = OneBoxUnderCamera();
  const RenderedFrame frame = RenderFrame(spec, 0);
  const auto& ids = frame.flat.at("instanceid").Get("id").uints;
  const auto& depth = frame.flat.at("depth").Get("Z").floats;
  const auto& nz = frame.flat.at("normal").Get("Z").floats;
  const auto& pz = frame.flat.at("worldposition").Get("Z").floats;
  int ground = 0;
  for (size_t p = 0; p < ids.size(); ++p) {
    if (ids[p] == 1000) {  // ground: planar depth is the altitude everywhere
      EXPECT_FLOAT_EQ(depth[p], 20.0f);
      EXPECT_FLOAT_EQ(nz[p], 1.0f);
      EXPECT_NEAR(pz[p], 0.0f, 1e-5);
      ++ground;
    } else {
      EXPECT_EQ(ids[p], 1u);
      EXPECT_FLOAT_EQ(depth[p], 18.0f);  // only the top face is visible from straight above
    }
  }
  EXPECT_GT(ground, 0);
}

TEST(Synth, BoxCoversTheAnalyticPixels) {
  const Spec spec = OneBoxUnderCamera();
  const RenderedFrame frame = RenderFrame(spec, 0);
  const PinholeCamera camera =
      PinholeCamera::FromHorizontalFov(spec.width, spec.height, spec.hfov_deg);
  // The top face (2 m square at 18 m) projects to a square of side 2 * fx / 18
  // around the centre.
  const double half = camera.fx / 18.0;
  int expected = 0, x0 = 1 << 20, x1 = -1, y0 = 1 << 20, y1 = -1;
  for (int j = 0; j < spec.height; ++j) {
    for (int i = 0; i < spec.width; ++i) {
      if (std::abs(i + 0.5 - camera.cx) < half && std::abs(j + 0.5 - camera.cy) < half) {
        ++expected;
        x0 = std::min(x0, i), x1 = std::max(x1, i + 1), y0 = std::min(y0, j),
        y1 = std::max(y1, j + 1);
      }
    }
  }
  ASSERT_EQ(frame.truth.objects.size(), 1u);
  const ObjectTruth& object = frame.truth.objects[0];
  EXPECT_EQ(object.visible_pixels, expected);
  ASSERT_TRUE(object.bbox);
  EXPECT_EQ(*object.bbox, (Box2d{double(x0), double(y0), double(x1), double(y1)}));
  EXPECT_DOUBLE_EQ(object.visibility, 1.0);
  EXPECT_DOUBLE_EQ(object.in_frame, 1.0);
  ASSERT_TRUE(object.bbox_projected);
  EXPECT_TRUE(object.bbox_projected->Contains(*object.bbox, 1e-9));
}

TEST(Synth, ShadowBehindTheBoxAndNoneInTheOpen) {
  const Spec spec = OneBoxUnderCamera();
  const RenderedFrame frame = RenderFrame(spec, 0);
  const auto& shadow = frame.flat.at("shadow").Get("Y").floats;
  const auto& px = frame.flat.at("worldposition").Get("X").floats;
  const auto& py = frame.flat.at("worldposition").Get("Y").floats;
  const auto& ids = frame.flat.at("instanceid").Get("id").uints;
  const double cosine = spec.direction_to_sun.z();
  int shadowed = 0, open = 0;
  for (size_t p = 0; p < shadow.size(); ++p) {
    if (ids[p] != 1000) continue;
    // Ground points whose ray to the sun crosses the box: between the box and
    // its shadow tip.
    const Eigen::Vector3d point(px[p], py[p], 0);
    const double t_top = 2.0 / spec.direction_to_sun.z();
    const Eigen::Vector3d tip = point + t_top * spec.direction_to_sun;
    // Shadow of the 2 m box for this sun: x in (-1 - 2 * sx / sz, -1), away
    // from the y edges.
    if (point.x() > -1.5 && point.x() < -1.05 && std::abs(point.y()) < 0.6) {
      EXPECT_NEAR(shadow[p], 0.3 / (0.3 + cosine), 1e-6) << "at " << point.transpose();
      ++shadowed;
    }
    if (point.x() > 2 || point.y() > 2 || tip.x() < -1.5) {  // the sun ray climbs away from the box
      EXPECT_FLOAT_EQ(shadow[p], 1.0f);
      ++open;
    }
  }
  EXPECT_GT(shadowed, 0);
  EXPECT_GT(open, 0);
}

TEST(Synth, MotionMatchesTheCameraStep) {
  const Spec spec = OneBoxUnderCamera();
  const PinholeCamera camera =
      PinholeCamera::FromHorizontalFov(spec.width, spec.height, spec.hfov_deg);
  const RenderedFrame first = RenderFrame(spec, 0);
  const RenderedFrame second = RenderFrame(spec, 1);
  // The first frame of the shot has no valid motion: NaN, never 0.5.
  for (float m : first.flat.at("motion").Get("X").floats) EXPECT_TRUE(std::isnan(m));
  // The camera moved 1 m east at 20 m: ground points moved fx / 20 pixels to
  // the left.
  const auto& ids = second.flat.at("instanceid").Get("id").uints;
  const auto& mx = second.flat.at("motion").Get("X").floats;
  const auto& my = second.flat.at("motion").Get("Y").floats;
  const float expected = static_cast<float>(0.5 - 0.5 * (camera.fx / 20.0) / spec.width);
  for (size_t p = 0; p < ids.size(); ++p) {
    if (ids[p] != 1000) continue;
    // Ground entering on the right was outside the previous image: NaN.
    const double x = static_cast<double>(p % spec.width) + 0.5;
    if (x + camera.fx / 20.0 >= spec.width) {
      EXPECT_TRUE(std::isnan(mx[p]) && std::isnan(my[p])) << p;
      continue;
    }
    if (std::isnan(mx[p])) {  // disoccluded from behind the box
      EXPECT_TRUE(std::isnan(my[p]));
      continue;
    }
    EXPECT_NEAR(mx[p], expected, 1e-6);
    EXPECT_NEAR(my[p], 0.5f, 1e-6);
  }
}

TEST(Synth, PerspectiveDepthIsPlanarOverCosine) {
  Spec spec = OneBoxUnderCamera();
  const RenderedFrame planar = RenderFrame(spec, 0);
  spec.depth_kind = DepthKind::kPerspective;
  const RenderedFrame perspective = RenderFrame(spec, 0);
  const PinholeCamera camera =
      PinholeCamera::FromHorizontalFov(spec.width, spec.height, spec.hfov_deg);
  for (int j = 0; j < spec.height; ++j) {
    for (int i = 0; i < spec.width; ++i) {
      const size_t p = static_cast<size_t>(j) * spec.width + i;
      const double cosine = camera.RayThroughPixelCenter(i, j).normalized().z();
      EXPECT_NEAR(perspective.flat.at("depth").Get("Z").floats[p],
                  planar.flat.at("depth").Get("Z").floats[p] / cosine,
                  1e-4);
    }
  }
}

TEST(Synth, BundleCentreSampleEqualsSingleValueLayers) {
  Spec spec = DefaultSpec();
  spec.samples_per_axis = 3;
  const RenderedFrame frame = RenderFrame(spec, 1);
  const exr::DeepImage& bundle = frame.bundle;
  int mixed = 0;
  for (int j = 0; j < spec.height; ++j) {
    for (int i = 0; i < spec.width; ++i) {
      const size_t p = bundle.Index(i, j);
      const uint64_t first = bundle.FirstSample(i, j);
      ASSERT_EQ(bundle.SampleCount(i, j), 9u);
      EXPECT_EQ(bundle.Get("instanceid").uints[first],
                frame.flat.at("instanceid").Get("id").uints[p]);
      EXPECT_EQ(bundle.Get("classid").uints[first], frame.flat.at("classid").Get("id").uints[p]);
      EXPECT_EQ(bundle.Get("Z").floats[first], frame.flat.at("depth").Get("Z").floats[p]);
      EXPECT_EQ(bundle.Get("SX").floats[first], 0.5f);
      bool is_mixed = false;
      for (uint32_t k = 1; k < 9; ++k) {
        is_mixed |=
            bundle.Get("instanceid").uints[first + k] != bundle.Get("instanceid").uints[first];
      }
      mixed += is_mixed;
    }
  }
  EXPECT_GT(mixed, 0);  // box edges
  EXPECT_LT(mixed, spec.width * spec.height / 4);
}

}  // namespace
}  // namespace lsds::synth
