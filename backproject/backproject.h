// Back-projection of one frame's depth layer into points: the per-pixel
// arithmetic, free of I/O and of PCL. The collection-level driver (streaming,
// poses, outputs) is backproject_run.h.
#pragma once

#include <cstdint>

#include <Eigen/Geometry>

#include "backproject/point_cloud.h"
#include "libs/geometry/camera.h"

namespace lsds::pointcloud {

// Views into a frame's decoded layers, row-major, width * height values each.
// Optional layers are null. Depth is in world units, of the declared kind;
// normals are unit vectors in the world frame.
struct FrameLayers {
  int width = 0;
  int height = 0;
  const float* depth = nullptr;
  DepthKind depth_kind = DepthKind::kPlanar;
  const float* red = nullptr;  // scene-linear
  const float* green = nullptr;
  const float* blue = nullptr;
  const uint32_t* class_id = nullptr;
  const uint32_t* instance_id = nullptr;
  const float* normal_x = nullptr;
  const float* normal_y = nullptr;
  const float* normal_z = nullptr;
};

// Where the points go: `out_from_cam` maps the OpenCV camera frame (world
// units) to the output frame (the identity for camera-frame output).
// `out_from_world_normal` rotates world-frame normals into the output frame.
// Affine rather than rigid because a declared world may be left-handed
// (Unreal).
struct FramePose {
  PinholeCamera camera;
  Eigen::Affine3d out_from_cam = Eigen::Affine3d::Identity();
  Eigen::Matrix3d out_from_world_normal = Eigen::Matrix3d::Identity();
};

// True for a depth that is a surface: finite and > 0 (sky is +inf; NaN and
// negatives are invalid).
inline bool IsValidDepth(float depth) { return depth > 0.0f && depth < INFINITY; }

// Appends one point per valid pixel of every `stride`-th row and column (pixel
// centres) to `cloud`. `cloud->attributes` says which attributes to fill; the
// layers for them must be present.
void BackprojectFrame(const FrameLayers& layers,
                      const FramePose& pose,
                      int stride,
                      PointCloud* cloud);

// Scene-linear value -> sRGB 8 bit: clamp to [0, 1], sRGB transfer curve. NaN
// -> 0.
uint8_t ToneMap(float linear);

// Distances between back-projected points and the world-position layer.
struct ErrorStats {
  int64_t compared = 0;  // pixels with valid depth and finite truth
  double max_error = 0;
  double sum_squared = 0;
  double rms() const;
  void Merge(const ErrorStats& other);
};

// Back-projects every `stride`-th valid pixel with `world_from_cam` (double
// precision) and compares with the world-position layer (world units).
ErrorStats CompareWithWorldPosition(const FrameLayers& layers,
                                    const PinholeCamera& camera,
                                    const Eigen::Affine3d& world_from_cam,
                                    int stride,
                                    const float* world_x,
                                    const float* world_y,
                                    const float* world_z);

}  // namespace lsds::pointcloud
