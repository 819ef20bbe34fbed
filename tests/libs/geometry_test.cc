#include <cmath>

#include <gtest/gtest.h>

#include "libs/geometry/attitude.h"
#include "libs/geometry/camera.h"
#include "libs/geometry/oriented_box.h"
#include "libs/geometry/world_frame.h"

namespace lsds {
namespace {

TEST(Camera, FromFovMatchesFormula) {
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(640, 480, 90.0);
  EXPECT_DOUBLE_EQ(camera.fx, 320.0);  // tan(45 deg) == 1
  EXPECT_DOUBLE_EQ(camera.cx, 320.0);
  EXPECT_DOUBLE_EQ(camera.cy, 240.0);
  EXPECT_NEAR(camera.HorizontalFovDeg(), 90.0, 1e-12);
}

TEST(Camera, ProjectUnprojectRoundTrip) {
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(1024, 768, 63.0);
  for (double u : {0.0, 0.5, 100.25, 1023.9}) {
    for (double v : {0.0, 383.5, 767.0}) {
      for (double depth : {0.1, 7.0, 1234.5}) {
        const Eigen::Vector3d point = camera.CamFromImage({u, v}) * depth;
        const Eigen::Vector2d pixel = camera.ImageFromCam(point);
        EXPECT_NEAR(pixel.x(), u, 1e-9);
        EXPECT_NEAR(pixel.y(), v, 1e-9);
      }
    }
  }
}

TEST(Camera, PixelCentreConvention) {
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(4, 4, 90.0);
  // The optical axis passes between the four central pixels, at (2, 2).
  EXPECT_EQ(camera.CamFromImage({2.0, 2.0}), Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(camera.RayThroughPixelCenter(1, 1), camera.CamFromImage({1.5, 1.5}));
}

TEST(Camera, PlanarPerspectiveRoundTrip) {
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(200, 100, 70.0);
  const Eigen::Vector2d pixel(13.5, 91.5);
  const double planar = 12.0;
  const double perspective = PerspectiveFromPlanarDepth(camera, pixel, planar);
  // perspective = planar / cos(angle between ray and axis)
  const Eigen::Vector3d ray = camera.CamFromImage(pixel);
  EXPECT_NEAR(perspective, planar / (ray.normalized().z()), 1e-12);
  EXPECT_NEAR(PlanarFromPerspectiveDepth(camera, pixel, perspective), planar, 1e-12);
  EXPECT_TRUE(
      UnprojectDepth(camera, pixel, planar, DepthKind::kPlanar)
          .isApprox(UnprojectDepth(camera, pixel, perspective, DepthKind::kPerspective), 1e-12));
}

TEST(Attitude, RoundTripAwayFromGimbalLock) {
  for (double roll : {-30.0, 0.0, 12.0}) {
    for (double pitch : {-60.0, -5.0, 40.0}) {
      for (double yaw : {-170.0, 0.0, 95.0}) {
        const Rigid3d cam_from_enu = CamFromEnu({1, 2, 3}, Attitude{roll, pitch, yaw});
        Eigen::Vector3d position;
        Attitude attitude;
        PositionAndAttitudeFromCamFromEnu(cam_from_enu, &position, &attitude);
        EXPECT_TRUE(position.isApprox(Eigen::Vector3d(1, 2, 3), 1e-12));
        EXPECT_NEAR(attitude.roll_deg, roll, 1e-9);
        EXPECT_NEAR(attitude.pitch_deg, pitch, 1e-9);
        EXPECT_NEAR(attitude.yaw_deg, yaw, 1e-9);
      }
    }
  }
}

TEST(Attitude, LevelCameraLooksNorthAndNadirLooksDown) {
  const Rigid3d level = CamFromEnu(Eigen::Vector3d::Zero(), Attitude{0, 0, 0});
  // The optical axis (camera z) points north (ENU +y); image y (down) points to
  // ENU -z.
  EXPECT_TRUE((level.rotation.conjugate() * Eigen::Vector3d::UnitZ())
                  .isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_TRUE((level.rotation.conjugate() * Eigen::Vector3d::UnitY())
                  .isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
  const Rigid3d nadir = CamFromEnu(Eigen::Vector3d::Zero(), Attitude{0, -90, 0});
  EXPECT_TRUE((nadir.rotation.conjugate() * Eigen::Vector3d::UnitZ())
                  .isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
}

TEST(WorldFrame, UnrealCentimetresToEnuMetres) {
  const WorldFrame unreal = WorldFrame::Make("unreal", "cm");
  EXPECT_FALSE(unreal.right_handed());
  // Unreal x is north, y east, z up, in centimetres.
  EXPECT_TRUE(unreal.EnuMetresFromWorld({100, 200, 300}).isApprox(Eigen::Vector3d(2, 1, 3)));
  EXPECT_TRUE(unreal.WorldFromEnuMetres({2, 1, 3}).isApprox(Eigen::Vector3d(100, 200, 300)));
  // A declared pose with a reflection becomes a proper rotation in ENU metres.
  const Rigid3d cam_from_enu = CamFromEnu({5, 6, 7}, Attitude{3, -20, 40});
  const Eigen::Matrix3d declared_rotation =
      cam_from_enu.rotation.toRotationMatrix() * unreal.enu_from_frame;
  const Eigen::Vector3d declared_translation = cam_from_enu.translation / unreal.metres_per_unit;
  const Rigid3d back = unreal.CamFromEnuMetres(declared_rotation, declared_translation);
  EXPECT_TRUE(back.rotation.isApprox(cam_from_enu.rotation, 1e-12));
  EXPECT_TRUE(back.translation.isApprox(cam_from_enu.translation, 1e-12));
  EXPECT_THROW(WorldFrame::Make("EUN", "m"), std::exception);
  EXPECT_THROW(WorldFrame::Make("ENU", "feet"), std::exception);
}

TEST(OrientedBox, CornersAndIntersection) {
  OrientedBox a;
  a.half_extents = {1, 2, 3};
  const auto corners = a.Corners();
  EXPECT_EQ(corners[0], Eigen::Vector3d(-1, -2, -3));
  EXPECT_EQ(corners[7], Eigen::Vector3d(1, 2, 3));
  OrientedBox b = a;
  b.center = {1.9, 0, 0};
  EXPECT_TRUE(a.Intersects(b));
  b.center = {2.0, 0, 0};  // touching is not intersecting
  EXPECT_FALSE(a.Intersects(b));
  b.world_from_box = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  b.center = {2.2, 0, 0};
  EXPECT_TRUE(a.Intersects(b));
}

TEST(OrientedBox, ProjectionAndInFrameFraction) {
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(100, 100, 90.0);  // fx = 50
  const Rigid3d cam_from_world;  // identity: world == camera frame
  OrientedBox box;
  box.center = {0, 0, 10};
  box.half_extents = {1, 1, 1e-9};  // a 2 m square at 10 m: 10 px wide around the centre
  const auto bounds = ProjectedBounds(box, camera, cam_from_world);
  ASSERT_TRUE(bounds);
  EXPECT_NEAR(bounds->x0, 45, 1e-6);
  EXPECT_NEAR(bounds->x1, 55, 1e-6);
  EXPECT_NEAR(InFrameFraction(box, camera, cam_from_world), 1.0, 1e-9);
  box.center = {10, 0, 10};  // centred on the right edge: half inside
  EXPECT_NEAR(InFrameFraction(box, camera, cam_from_world), 0.5, 1e-6);
  box.center = {0, 0, -10};  // behind the camera
  EXPECT_FALSE(ProjectedBounds(box, camera, cam_from_world));
  EXPECT_EQ(InFrameFraction(box, camera, cam_from_world), 0.0);
}

}  // namespace
}  // namespace lsds
