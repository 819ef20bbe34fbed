// Voxel-grid downsampling: at most one point per voxel, ids never averaged.
#include <random>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "backproject/backproject_run.h"
#include "backproject/cloud_io.h"
#include "backproject/voxel_grid.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tests/backproject/test_util.h"

namespace lsds::pointcloud {
namespace {

size_t DistinctVoxels(const PointCloud& cloud, double size) {
  std::set<std::tuple<int64_t, int64_t, int64_t>> keys;
  for (const CloudPoint& p : cloud.points) {
    const VoxelKey k = VoxelOf(p.x, p.y, p.z, size);
    keys.insert({k.x, k.y, k.z});
  }
  return keys.size();
}

TEST(VoxelGrid, FusedCloudOfOverlappingFramesHasAtMostOnePointPerVoxel) {
  testing::ScratchDir dir("voxel");
  synth::Spec spec = synth::DefaultSpec();  // 4 frames 1 m apart: they overlap mostly
  const auto collection = testing::WriteSynth(dir / "c", spec);
  for (double voxel : {0.5, 0.25, 0.1, 1e-4}) {
    BackprojectOptions options;
    options.collection = collection;
    options.output = dir / "fused.pcd";
    options.fuse = true;
    options.voxel = voxel;
    options.force = true;
    const BackprojectSummary summary = RunBackproject(options);
    const PointCloud cloud = ReadCloud(options.output);
    ASSERT_EQ(static_cast<int64_t>(cloud.points.size()), summary.points_written);
    EXPECT_EQ(DistinctVoxels(cloud, voxel), cloud.points.size()) << "voxel " << voxel;
    // Pixels are ~0.36 m apart on the ground: big voxels merge points, tiny
    // ones keep every point.
    if (voxel >= 0.5) {
      EXPECT_LT(summary.points_written, summary.points_backprojected / 2);
    }
    EXPECT_LE(summary.points_written, summary.points_backprojected);
    EXPECT_GT(summary.points_written, 0);
    for (const CloudPoint& p : cloud.points) ASSERT_TRUE(p.label >= 1 && p.label <= 3);
  }
}

TEST(VoxelGrid, CentroidsOnVoxelFacesStayInTheirVoxel) {
  // Points crowding the far face of a voxel: their centroid rounds onto the
  // face in float.
  const double size = 0.1;
  PointCloud cloud;
  cloud.attributes.labels = true;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> cell(-50, 50);
  for (int i = 0; i < 20000; ++i) {
    const float face = static_cast<float>((cell(rng) + 1) * size);
    CloudPoint p{};
    p.x = std::nextafter(face, -INFINITY);
    p.y = std::nextafter(std::nextafter(face, -INFINITY), -INFINITY);
    p.z = static_cast<float>(cell(rng) * size);
    p.label = 7;
    cloud.points.push_back(p);
  }
  VoxelAccumulator grid(size, cloud.attributes);
  grid.Add(cloud);
  const PointCloud out = grid.Finish();
  EXPECT_EQ(DistinctVoxels(out, size), out.points.size());
  EXPECT_EQ(out.points.size(), grid.voxel_count());
  std::set<std::tuple<int64_t, int64_t, int64_t>> input_keys;
  for (const CloudPoint& p : cloud.points) {
    const VoxelKey k = VoxelOf(p.x, p.y, p.z, size);
    input_keys.insert({k.x, k.y, k.z});
  }
  for (const CloudPoint& p : out.points) {
    const VoxelKey k = VoxelOf(p.x, p.y, p.z, size);
    ASSERT_TRUE(input_keys.count({k.x, k.y, k.z})) << "a centroid left its voxel";
    ASSERT_EQ(p.label, 7u);
  }
  EXPECT_THROW(VoxelAccumulator(0, Attributes{}), Error);
}

}  // namespace
}  // namespace lsds::pointcloud
