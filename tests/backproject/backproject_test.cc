// Back-projection on analytic collections: geometry against exact truth.
#include <cmath>

#include <gtest/gtest.h>

#include "backproject/backproject_run.h"
#include "backproject/cloud_io.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/collection/json_io.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tests/backproject/test_util.h"

namespace lsds::pointcloud {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::WriteSynth;

// An oblique camera too, so that perspective and planar depth differ noticeably
// off-axis.
synth::Spec GroundOnly(DepthKind kind) {
  synth::Spec spec = synth::DefaultSpec();
  spec.boxes.clear();
  spec.depth_kind = kind;
  spec.cam_from_world = {synth::NadirCamFromWorld({0, 0, 20}), LookAt({-15, -10, 12}, {0, 0, 0})};
  return spec;
}

PointCloud Fuse(const fs::path& collection, const fs::path& out, BackprojectOptions options = {}) {
  options.collection = collection;
  options.output = out;
  options.fuse = true;
  RunBackproject(options);
  return ReadCloud(out);
}

TEST(Backproject, PlaneAtKnownDistanceBackprojectsOntoThatPlane) {
  for (DepthKind kind : {DepthKind::kPlanar, DepthKind::kPerspective}) {
    ScratchDir dir(std::string("plane_") + DepthKindName(kind));
    const fs::path collection = WriteSynth(dir / "c", GroundOnly(kind));
    const PointCloud world = Fuse(collection, dir / "world.pcd");
    synth::Spec spec = GroundOnly(kind);
    // Every pixel of the nadir frame and the lower part of the oblique one see
    // the ground.
    ASSERT_GT(world.points.size(), static_cast<size_t>(spec.width * spec.height));
    for (const CloudPoint& p : world.points) ASSERT_NEAR(p.z, 0.0f, 2e-5) << DepthKindName(kind);

    // In the nadir camera's frame the ground is the plane z = 20 (m).
    BackprojectOptions options;
    options.frame = OutputFrame::kCamera;
    options.frames = {0, 1};
    const PointCloud camera = Fuse(collection, dir / "camera.pcd", options);
    ASSERT_EQ(camera.points.size(), static_cast<size_t>(spec.width * spec.height));
    for (const CloudPoint& p : camera.points) ASSERT_NEAR(p.z, 20.0f, 2e-5) << DepthKindName(kind);
  }
}

TEST(Backproject, PlanarAndPerspectiveDepthGiveTheSamePoints) {
  ScratchDir dir("kinds");
  synth::Spec planar = synth::DefaultSpec();
  planar.cam_from_world.push_back(LookAt({-15, -10, 12}, {0, 0, 0}));
  synth::Spec perspective = planar;
  perspective.depth_kind = DepthKind::kPerspective;
  const PointCloud a = Fuse(WriteSynth(dir / "planar", planar), dir / "a.pcd");
  const PointCloud b = Fuse(WriteSynth(dir / "perspective", perspective), dir / "b.pcd");
  ASSERT_EQ(a.points.size(), b.points.size());
  ASSERT_GT(a.points.size(), 1000u);
  double max_distance = 0;
  for (size_t i = 0; i < a.points.size(); ++i) {
    const CloudPoint& p = a.points[i];
    const CloudPoint& q = b.points[i];
    max_distance = std::max<double>(max_distance, std::hypot(p.x - q.x, p.y - q.y, p.z - q.z));
    ASSERT_EQ(p.label, q.label);
    ASSERT_EQ(p.instance, q.instance);
  }
  EXPECT_LT(max_distance, 3e-5);  // float depth at ~25 m
}

TEST(Backproject, CameraFrameOutputTransformedByThePoseEqualsWorldFrameOutput) {
  ScratchDir dir("frames");
  synth::Spec spec = synth::DefaultSpec();
  spec.cam_from_world.push_back(LookAt({-15, -10, 12}, {0, 0, 1}));
  const fs::path collection = WriteSynth(dir / "c", spec);
  BackprojectOptions options;
  options.collection = collection;
  options.output = dir / "world";
  RunBackproject(options);
  options.output = dir / "camera";
  options.frame = OutputFrame::kCamera;
  options.normals = true;
  RunBackproject(options);

  CollectionReader reader(collection);
  int frames = 0;
  reader.ForEachFrame([&](const Frame& frame) {
    const std::string file = FrameStem(frame.index) + ".pcd";
    const PointCloud world = ReadCloud(dir / "world" / file);
    const PointCloud camera = ReadCloud(dir / "camera" / file);
    ASSERT_EQ(world.points.size(), camera.points.size());
    const Rigid3d cam_from_world(Eigen::Quaterniond(frame.camera.cam_from_world_rotation),
                                 frame.camera.cam_from_world_translation);
    const Rigid3d world_from_cam = cam_from_world.Inverse();
    for (size_t i = 0; i < world.points.size(); ++i) {
      const CloudPoint& c = camera.points[i];
      const Eigen::Vector3d mapped = world_from_cam * Eigen::Vector3d(c.x, c.y, c.z);
      const CloudPoint& w = world.points[i];
      ASSERT_LT((mapped - Eigen::Vector3d(w.x, w.y, w.z)).norm(), 3e-5) << "frame " << frame.index;
      // Camera-frame normals face the camera: the point is in front, the normal
      // points back.
      ASSERT_LT(
          Eigen::Vector3d(c.normal_x, c.normal_y, c.normal_z).dot(Eigen::Vector3d(c.x, c.y, c.z)),
          0);
    }
    ++frames;
  });
  EXPECT_EQ(frames, 5);
}

TEST(Backproject, CheckIsAtFloatPrecisionOnTruthPosesAndShowsMetadataErrors) {
  ScratchDir dir("check");
  synth::Spec spec = synth::DefaultSpec();
  spec.depth_kind = DepthKind::kPerspective;
  const fs::path collection = WriteSynth(dir / "c", spec);
  BackprojectOptions options;
  options.collection = collection;
  options.check = true;
  int frames = 0;
  BackprojectSummary summary = RunBackproject(options, [&](const FrameReport& r) {
    EXPECT_TRUE(r.checked);
    EXPECT_EQ(r.check.compared, spec.width * spec.height);
    EXPECT_LT(r.check.max_error, 1e-5);  // ~20 m in float: ulp 2e-6
    ++frames;
  });
  EXPECT_EQ(frames, 4);
  EXPECT_LT(summary.check.rms(), 5e-6);

  // The truth metadata's poses (position + attitude) give the same points.
  options.metadata = "metadata.json";
  summary = RunBackproject(options);
  EXPECT_LT(summary.check.max_error, 1e-5);

  // A variant whose positions are 0.5 m off east: the registration error shows
  // as 0.5 m everywhere.
  {
    MetadataReader truth(collection / "metadata.json");
    MetadataHeader header = truth.header();
    header.perturbed = true;
    MetadataWriter writer(collection / "metadata.shifted.json", header);
    truth.ForEachFrame([&](const MetadataFrame& m) {
      MetadataFrame shifted = m;
      shifted.position.x() += 0.5;
      writer.Append(shifted);
    });
    writer.Commit();
  }
  options.metadata = collection / "metadata.shifted.json";
  summary = RunBackproject(options);
  EXPECT_NEAR(summary.check.max_error, 0.5, 1e-4);
  EXPECT_NEAR(summary.check.rms(), 0.5, 1e-4);
}

TEST(Backproject, PointsCarryLabelsColoursAndNormals) {
  ScratchDir dir("attributes");
  const fs::path collection = WriteSynth(dir / "c", synth::DefaultSpec());
  BackprojectOptions options;
  options.normals = true;
  const PointCloud cloud = Fuse(collection, dir / "all.ply", options);
  ASSERT_TRUE(cloud.attributes.rgb && cloud.attributes.labels && cloud.attributes.normals);
  int ground = 0, boxes = 0, coloured = 0;
  for (const CloudPoint& p : cloud.points) {
    if (p.instance == 1000) {  // the ground plane
      ++ground;
      ASSERT_EQ(p.label, 1u);
      ASSERT_NEAR(p.z, 0, 2e-5);
      ASSERT_NEAR(p.normal_z, 1.0f, 1e-6);
    } else {
      ++boxes;
      ASSERT_TRUE(p.label == 2 || p.label == 3);
      ASSERT_GT(p.z, 0.0f);
      // Boxes stand upright: tops face up, sides are horizontal.
      ASSERT_TRUE(std::abs(p.normal_z - 1.0f) < 1e-6f || std::abs(p.normal_z) < 1e-6f)
          << p.normal_z;
    }
    if (p.rgb != 0) ++coloured;
  }
  EXPECT_GT(ground, 0);
  EXPECT_GT(boxes, 0);
  EXPECT_GT(coloured, static_cast<int>(cloud.points.size()) / 2);
}

TEST(Backproject, StrideAndFrameRangeSelectPixelsAndFrames) {
  ScratchDir dir("stride");
  synth::Spec spec = synth::DefaultSpec();
  const fs::path collection = WriteSynth(dir / "c", spec);
  BackprojectOptions options;
  options.collection = collection;
  options.output = dir / "out";
  options.stride = 2;
  options.frames = {1, 3};
  const BackprojectSummary summary = RunBackproject(options);
  EXPECT_EQ(summary.frames, 2);
  EXPECT_EQ(testing::ListDir(dir / "out"), "000001.pcd 000002.pcd ");
  EXPECT_EQ(ReadCloud(dir / "out" / "000001.pcd").points.size(),
            static_cast<size_t>((spec.width / 2) * (spec.height / 2)));
}

}  // namespace
}  // namespace lsds::pointcloud

namespace lsds::pointcloud {
namespace {

// Metadata poses (camera centre + attitude) map to the same world points as
// the declared truth pose, in every declared world frame and unit.
TEST(Backproject, MetadataPosesMatchTruthPosesInEveryWorldFrame) {
  const Rigid3d cam_from_enu_m = LookAt({-15, -10, 12}, {1, 2, 0});
  for (const auto& [name, unit] : std::vector<std::pair<std::string, std::string>>{
           {"ENU", "m"}, {"NED", "m"}, {"unreal", "cm"}, {"ENU", "mm"}}) {
    const WorldFrame world = WorldFrame::Make(name, unit);
    // Declared pose: p_cam[unit] = R p_world + t with R = R_ce * F.
    Frame frame;
    frame.camera.intrinsics = PinholeCamera::FromHorizontalFov(64, 48, 60);
    frame.camera.cam_from_world_rotation =
        cam_from_enu_m.rotation.toRotationMatrix() * world.enu_from_frame;
    frame.camera.cam_from_world_translation = cam_from_enu_m.translation / world.metres_per_unit;
    const MetadataFrame metadata = TruthMetadata(frame, world);
    const Eigen::Affine3d truth = WorldFromCamOfTruth(frame.camera);
    const Eigen::Affine3d measured = WorldFromCamOfMetadata(world, metadata);
    for (const Eigen::Vector3d& p_cam : {Eigen::Vector3d(0, 0, 10), Eigen::Vector3d(3, -2, 25)}) {
      const Eigen::Vector3d p = p_cam / world.metres_per_unit;
      EXPECT_LT((truth * p - measured * p).norm() * world.metres_per_unit, 1e-9)
          << name << " " << unit;
      // And the world point is where the ENU-metre pose puts it.
      const Eigen::Vector3d enu = cam_from_enu_m.Inverse() * p_cam;
      EXPECT_LT((world.EnuMetresFromWorld(truth * p) - enu).norm(), 1e-9) << name << " " << unit;
    }
  }
}

}  // namespace
}  // namespace lsds::pointcloud
