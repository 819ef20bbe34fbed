// Point cloud files, written and read with PCL. PCL stays inside the plug-in lsds_cloud_io.so
// (cloud_io_plugin.cc), opened on first use: this header and this library are PCL-free. When the
// plug-in cannot be found or opened, WriteCloud and ReadCloud throw lsds::Error naming the paths
// tried (libs/util/plugin.h).
#pragma once

#include <filesystem>
#include <string>

#include "backproject/point_cloud.h"

namespace lsds::pointcloud {

enum class CloudFormat { kPcd, kPly };  // PCD binary, PLY binary little-endian

// The type of the label and instance properties of a PLY file: `int` (the default), which
// Open3D's tensor reader keeps and PCL's PCLPointCloud2 reads, or `uint`, which PCL's typed
// point types (pcl::PointXYZRGBL's uint32 label) read and Open3D drops. No one type serves both.
enum class PlyIds { kInt, kUint };
// "int" / "uint" -> PlyIds; anything else throws lsds::Error.
PlyIds PlyIdsFromName(const std::string& name);

// ".pcd" / ".ply" (case-insensitive) -> format; anything else throws
// lsds::Error naming `path`.
CloudFormat FormatFromPath(const std::filesystem::path& path);
// "pcd" / "ply" -> format; anything else throws lsds::Error.
CloudFormat FormatFromName(const std::string& name);
const char* Extension(CloudFormat format);  // ".pcd" | ".ply"

// Writes atomically (temporary file beside `path`, then rename): an error
// leaves nothing behind. Fields: x y z, then rgb, label instance, normal_x
// normal_y normal_z as `cloud.attributes` says.
void WriteCloud(const std::filesystem::path& path,
                const PointCloud& cloud,
                CloudFormat format,
                PlyIds ply_ids = PlyIds::kInt);

// Reads a PCD or PLY file (by extension) with PCL; the attributes are the
// fields present.
PointCloud ReadCloud(const std::filesystem::path& path);

}  // namespace lsds::pointcloud
