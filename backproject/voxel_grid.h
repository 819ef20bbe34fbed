// Exact voxel-grid downsampling: at most one point per voxel, streamed.
//
// Why not pcl::VoxelGrid: it averages every field, so class and instance ids of
// a voxel become the mean of several ids (meaningless), and when the grid would
// have more than 2^31 cells it logs a warning and returns the input unfiltered,
// which breaks "one point per voxel". This hash has neither limit and accepts
// points frame by frame, so memory is bounded by the output (one cell per
// voxel).
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>

#include "backproject/point_cloud.h"

namespace lsds::pointcloud {

// Voxel (floor(x / size), floor(y / size), floor(z / size)) of a point.
struct VoxelKey {
  int64_t x = 0, y = 0, z = 0;
  bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
inline VoxelKey VoxelOf(float x, float y, float z, double size) {
  return {static_cast<int64_t>(std::floor(x / size)),
          static_cast<int64_t>(std::floor(y / size)),
          static_cast<int64_t>(std::floor(z / size))};
}

// One output point per occupied voxel: the centroid of the voxel's points
// (moved inside the voxel if rounding to float put it on the far face), the
// mean colour, the normalized mean normal, and the class and instance ids of
// the point nearest the voxel centre (ids are never averaged).
class VoxelAccumulator {
 public:
  VoxelAccumulator(double size, Attributes attributes);
  ~VoxelAccumulator();
  void Add(const PointCloud& cloud);
  size_t voxel_count() const;
  // The downsampled cloud, voxels in first-seen order (deterministic for a
  // given input order).
  PointCloud Finish() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lsds::pointcloud
