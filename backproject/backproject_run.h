// `lsds backproject`: a collection's depth layers to point clouds, per frame or
// fused, streamed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>

#include "backproject/backproject.h"
#include "backproject/cloud_io.h"
#include "libs/collection/model.h"
#include "libs/util/frame_selection.h"

namespace lsds::pointcloud {

enum class OutputFrame { kWorld, kCamera };

// The map from a frame's camera (OpenCV, world units) to the declared world
// frame (world units): from the declared truth pose, or from a metadata frame's
// camera centre and attitude (against local NED) through the world frame.
Eigen::Affine3d WorldFromCamOfTruth(const CameraTruth& camera);
Eigen::Affine3d WorldFromCamOfMetadata(const WorldFrame& world, const MetadataFrame& metadata);

struct BackprojectOptions {
  std::filesystem::path collection;
  // Empty: nothing is written (e.g. --check alone). Per frame: a folder of
  // FRAME.pcd|ply files; fused: one file whose extension picks the format.
  std::filesystem::path output;
  std::string per_frame_format = "pcd";  // per-frame mode only
  PlyIds ply_ids = PlyIds::kInt;         // PLY outputs: the type of label and instance
  bool fuse = false;
  double voxel = 0;  // fused only; world units of the output frame; 0 = no downsampling
  OutputFrame frame = OutputFrame::kWorld;
  std::filesystem::path metadata;  // a metadata variant's poses instead of the truth poses
  bool check = false;
  bool normals = false;
  bool colors = true;  // when the collection has an rgb layer
  bool labels = true;  // when it has classid and instanceid layers
  int stride = 1;
  FrameRange frames;
  bool force = false;
  size_t batch_frames = 0;  // frames back-projected in parallel; 0 = 2 x hardware threads
};

struct FrameReport {
  int64_t index = 0;
  std::string stem;  // the frame's file stem ("000004_left" in a rig)
  int64_t points = 0;
  bool checked = false;
  ErrorStats check;  // world units
};

struct BackprojectSummary {
  int64_t frames = 0;
  int64_t points_backprojected = 0;
  int64_t points_written = 0;  // after voxel downsampling
  ErrorStats check;
  std::string world_unit;  // the declared length unit of the outputs and errors
};

// Runs the whole command. `on_frame` sees each frame's report in frame order.
// Throws lsds::Error for bad input (no depth layer, missing layers, unknown
// extension, unwritable output, ...); outputs are atomic, so nothing partial is
// left behind.
BackprojectSummary RunBackproject(const BackprojectOptions& options,
                                  const std::function<void(const FrameReport&)>& on_frame = {});

}  // namespace lsds::pointcloud
