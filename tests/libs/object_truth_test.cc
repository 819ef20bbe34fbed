// The oriented boxes of the object truth (MeasureObjectTruth,
// libs/collection/object_truth.h; docs/format.md, "Oriented boxes") on a
// car-sized box seen from straight above, against independent rules: the
// corners projected one by one, a brute-force minimum over angles, and the
// heading direction found by projecting two points.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "libs/collection/object_truth.h"
#include "tests/libs/brute_force_rectangle.h"

namespace lsds {
namespace {

using testing::BruteForceMinimumArea;

constexpr double kPi = 3.14159265358979323846;

struct Scene {
  PinholeCamera camera = PinholeCamera::FromHorizontalFov(160, 120, 60);
  // 40 m above the origin looking down, image up = world +y: world +x is the
  // image's right, world +y its top.
  Rigid3d cam_from_world = LookAt({0, 0, 40}, {0, 0, 0}, Eigen::Vector3d::UnitY());
  std::vector<uint32_t> ids = std::vector<uint32_t>(160 * 120, 0);
};

// A 4.2 x 1.8 x 1.5 m box on the ground at (x, y), turned `yaw_deg` about z.
OrientedBox Car(double x, double y, double yaw_deg) {
  OrientedBox box;
  box.center = {x, y, 0.75};
  box.half_extents = {2.1, 0.9, 0.75};
  box.world_from_box =
      Eigen::AngleAxisd(yaw_deg * kPi / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return box;
}

// Marks the pixels whose centre ray meets the box's top face with `id`.
void RasterizeTop(Scene* scene, const OrientedBox& box, uint32_t id) {
  const Rigid3d world_from_cam = scene->cam_from_world.Inverse();
  const double top = box.center.z() + box.half_extents.z();
  for (int j = 0; j < scene->camera.height; ++j) {
    for (int i = 0; i < scene->camera.width; ++i) {
      const Eigen::Vector3d origin = world_from_cam.translation;
      const Eigen::Vector3d ray =
          world_from_cam.rotation * scene->camera.RayThroughPixelCenter(i, j);
      const Eigen::Vector3d hit = origin + ray * ((top - origin.z()) / ray.z());
      const Eigen::Vector3d local = box.world_from_box.transpose() * (hit - box.center);
      if (std::abs(local.x()) <= box.half_extents.x() &&
          std::abs(local.y()) <= box.half_extents.y())
        scene->ids[static_cast<size_t>(j) * scene->camera.width + i] = id;
    }
  }
}

ObjectTruth Measure(const Scene& scene,
                    const OrientedBox& box,
                    uint32_t id,
                    std::optional<Eigen::Vector3d> heading_in_box) {
  ObjectIdentity identity;
  identity.instance_id = id;
  identity.class_id = 2;
  identity.obb = box;
  identity.heading_in_box = heading_in_box;
  const auto masks = MeasureInstanceMasks(scene.ids, scene.camera.width, scene.camera.height);
  const auto mask = masks.find(id);
  const std::optional<ObjectTruth> t =
      MeasureObjectTruth(identity,
                         scene.camera,
                         scene.cam_from_world,
                         {scene.ids.data(), scene.camera.width, scene.camera.height},
                         mask == masks.end() ? nullptr : &mask->second,
                         nullptr);
  EXPECT_TRUE(t);
  return t ? *t : ObjectTruth{};
}

std::vector<Eigen::Vector2d> ProjectedCorners(const Scene& scene, const OrientedBox& box) {
  std::vector<Eigen::Vector2d> points;
  for (const Eigen::Vector3d& corner : box.Corners())
    points.push_back(scene.camera.ImageFromCam(scene.cam_from_world * corner));
  return points;
}

// The image direction of the heading at the box centre, by projecting the
// centre and a point 1 mm ahead of it.
Eigen::Vector2d ImageHeading(const Scene& scene,
                             const OrientedBox& box,
                             const Eigen::Vector3d& heading) {
  const Eigen::Vector3d ahead = box.center + 1e-3 * box.world_from_box * heading;
  return scene.camera.ImageFromCam(scene.cam_from_world * ahead) -
         scene.camera.ImageFromCam(scene.cam_from_world * box.center);
}

// Corners 0 and 1 are the front side (outward normal closest to the heading)
// and corner 0 is on its left looking along the heading (left = (hy, -hx) on
// the image, y down); the corners run clockwise.
void ExpectHeadingFirst(const OrientedBox2d& box, const Eigen::Vector2d& heading) {
  auto normal = [&](int i) {
    return ((box.corners[i] + box.corners[(i + 1) % 4]) / 2 - box.Center()).normalized();
  };
  const Eigen::Vector2d h = heading.normalized();
  for (int i = 1; i < 4; ++i) EXPECT_GT(normal(0).dot(h), normal(i).dot(h));
  const Eigen::Vector2d mid = (box.corners[0] + box.corners[1]) / 2;
  EXPECT_GT((box.corners[0] - mid).dot(Eigen::Vector2d(h.y(), -h.x())), 0);
  const Eigen::Vector2d a = box.corners[1] - box.corners[0], b = box.corners[2] - box.corners[1];
  EXPECT_GT(a.x() * b.y() - a.y() * b.x(), 0);
}

TEST(ObjectTruthOrientedBoxes, VisibleBoxIsTheMasksMinimumRectangleHeadingFirst) {
  for (double yaw : {0.0, 90.0, 180.0, 270.0, 33.0}) {
    Scene scene;
    const OrientedBox car = Car(1.0, -0.5, yaw);
    RasterizeTop(&scene, car, 7);
    const ObjectTruth t = Measure(scene, car, 7, Eigen::Vector3d::UnitX());
    ASSERT_TRUE(t.bbox_oriented) << "yaw " << yaw;
    // Every pixel square of the mask is covered, with no more area than any
    // angle of a brute-force search finds.
    std::vector<Eigen::Vector2d> squares;
    for (int j = 0; j < scene.camera.height; ++j)
      for (int i = 0; i < scene.camera.width; ++i)
        if (scene.ids[static_cast<size_t>(j) * scene.camera.width + i] == 7)
          for (int d = 0; d < 4; ++d) squares.emplace_back(i + d % 2, j + d / 2);
    for (const Eigen::Vector2d& c : squares) ASSERT_TRUE(t.bbox_oriented->Contains(c, 1e-9));
    EXPECT_LE(t.bbox_oriented->Area(), BruteForceMinimumArea(squares) + 1e-9);
    const Eigen::Vector2d heading = ImageHeading(scene, car, Eigen::Vector3d::UnitX());
    ExpectHeadingFirst(*t.bbox_oriented, heading);
    ExpectHeadingFirst(*t.bbox_oriented_projected, heading);
  }
}

TEST(ObjectTruthOrientedBoxes, HeadingCornerInEachDirection) {
  // Seen from above with world +y up the image, a car facing +x (yaw 0) has
  // its front on the right side of the image and its front-left corner at the
  // top right; facing +y (90) the front is the top side, front-left top left.
  struct Case {
    double yaw;
    bool right, top;  // where corner 0 lies relative to the box centre
  };
  for (const Case& c : {Case{0, true, true},
                        Case{90, false, true},
                        Case{180, false, false},
                        Case{270, true, false}}) {
    Scene scene;
    const OrientedBox car = Car(0, 0, c.yaw);
    RasterizeTop(&scene, car, 3);
    const ObjectTruth t = Measure(scene, car, 3, Eigen::Vector3d::UnitX());
    for (const auto& box : {t.bbox_oriented, t.bbox_oriented_projected}) {
      ASSERT_TRUE(box);
      const Eigen::Vector2d offset = box->corners[0] - box->Center();
      EXPECT_EQ(offset.x() > 0, c.right) << "yaw " << c.yaw;
      EXPECT_EQ(offset.y() < 0, c.top) << "yaw " << c.yaw;
      // The front side is the short one (1.8 m across, not 4.2 m along).
      EXPECT_LT(box->Width(), box->Height()) << "yaw " << c.yaw;
    }
  }
}

TEST(ObjectTruthOrientedBoxes, NoHeadingKeepsTheCanonicalOrder) {
  Scene scene;
  const OrientedBox car = Car(0, 0, 33);
  RasterizeTop(&scene, car, 3);
  // No declared heading, or a heading along the line of sight (the box's z).
  for (const auto& heading : {std::optional<Eigen::Vector3d>(),
                              std::optional<Eigen::Vector3d>(Eigen::Vector3d::UnitZ())}) {
    const ObjectTruth t = Measure(scene, car, 3, heading);
    for (const auto& box : {t.bbox_oriented, t.bbox_oriented_projected}) {
      ASSERT_TRUE(box);
      for (int i = 1; i < 4; ++i) {
        EXPECT_TRUE(box->corners[0].y() < box->corners[i].y() ||
                    (box->corners[0].y() == box->corners[i].y() &&
                     box->corners[0].x() <= box->corners[i].x()));
      }
    }
  }
}

TEST(ObjectTruthOrientedBoxes, AmodalBoxCoversTheProjectedCornersUnclipped) {
  Scene scene;
  // Half out of the image on the right: the mask is cut, the amodal box not.
  const OrientedBox car = Car(22.5, 2, 20);
  RasterizeTop(&scene, car, 5);
  const ObjectTruth t = Measure(scene, car, 5, std::nullopt);
  ASSERT_TRUE(t.bbox_oriented && t.bbox_oriented_projected && t.bbox_projected);
  const std::vector<Eigen::Vector2d> corners = ProjectedCorners(scene, car);
  for (const Eigen::Vector2d& c : corners)
    EXPECT_TRUE(t.bbox_oriented_projected->Contains(c, 1e-9));
  EXPECT_LE(t.bbox_oriented_projected->Area(), BruteForceMinimumArea(corners) + 1e-9);
  EXPECT_GT(t.bbox_oriented_projected->Bounds().x1, scene.camera.width);
  EXPECT_LE(t.bbox_projected->x1, scene.camera.width);  // the axis-aligned one is clipped
  EXPECT_LE(t.bbox_oriented->Bounds().x1, scene.camera.width);
  EXPECT_LT(t.in_frame, 1.0);
}

TEST(ObjectTruthOrientedBoxes, HiddenObjectHasNoVisibleBox) {
  Scene scene;  // no pixel carries the id
  const ObjectTruth t = Measure(scene, Car(0, 0, 10), 9, Eigen::Vector3d::UnitX());
  EXPECT_FALSE(t.bbox_oriented);
  EXPECT_TRUE(t.bbox_oriented_projected);
}

// An object its source gives no 3D box for (an importer's 2D-only object): measured on its mask,
// nothing projected, visibility and in_frame not measured (1); no entry without a visible pixel.
TEST(ObjectTruthWithoutObb, MeasuredOnTheMaskOnly) {
  Scene scene;
  RasterizeTop(&scene, Car(1.0, -0.5, 33.0), 7);
  const auto masks =
      MeasureInstanceMasks(scene.ids.data(), scene.camera.width, scene.camera.height);
  ObjectIdentity identity;
  identity.instance_id = 7;
  identity.class_id = 2;
  const IdLayerView ids{scene.ids.data(), scene.camera.width, scene.camera.height};
  bool counted = false;
  const std::optional<ObjectTruth> t = MeasureObjectTruth(
      identity, scene.camera, scene.cam_from_world, ids, &masks.at(7), [&](const Box2d&) {
        counted = true;
        return int64_t{1} << 40;
      });
  ASSERT_TRUE(t);
  EXPECT_FALSE(t->obb);
  EXPECT_EQ(t->visible_pixels, masks.at(7).pixels);
  EXPECT_GT(t->visible_pixels, 0);
  EXPECT_EQ(t->bbox, masks.at(7).box);
  EXPECT_TRUE(t->bbox_oriented);
  EXPECT_FALSE(t->bbox_projected);
  EXPECT_FALSE(t->bbox_oriented_projected);
  EXPECT_EQ(t->visibility, 1.0);
  EXPECT_EQ(t->in_frame, 1.0);
  EXPECT_FALSE(counted);     // no box to count unoccluded pixels on
  identity.instance_id = 8;  // no pixel
  EXPECT_FALSE(
      MeasureObjectTruth(identity, scene.camera, scene.cam_from_world, ids, nullptr, nullptr));
}

TEST(ObjectTruthOrientedBoxes, BoxAcrossTheNearPlaneIsClipped) {
  // A camera inside a long box looking along it: the corners behind the
  // camera are replaced by the edges' crossings of the near plane, so the box
  // is finite and contains every corner in front of the camera.
  Scene scene;
  scene.cam_from_world = LookAt({0, 0, 1}, {10, 0, 1});
  OrientedBox box;
  box.center = {2, 0, 1};
  box.half_extents = {5, 1, 0.5};
  const ObjectTruth t = Measure(scene, box, 4, std::nullopt);
  ASSERT_TRUE(t.bbox_oriented_projected);
  for (const Eigen::Vector2d& c : t.bbox_oriented_projected->corners) EXPECT_TRUE(c.allFinite());
  for (const Eigen::Vector3d& corner : box.Corners()) {
    const Eigen::Vector3d in_cam = scene.cam_from_world * corner;
    if (in_cam.z() > 1e-3)
      EXPECT_TRUE(t.bbox_oriented_projected->Contains(scene.camera.ImageFromCam(in_cam), 1e-6));
  }
}

}  // namespace
}  // namespace lsds
