// The boundary between lsds and its point-cloud-files plug-in (backproject/cloud_io_plugin.cc),
// the only code that links PCL's io library (and through it VTK). cloud_io.cc builds the point
// layout; the plug-in turns it into a pcl::PCLPointCloud2 and back and calls PCL's PCD/PLY
// writers and readers. One extern "C" entry point returns a table of function pointers; both
// sides are built in one tree with the same libstdc++, so std::string and std::vector cross by
// reference.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lsds::pointcloud {

// Raised whenever the table's layout or meaning changes; the loader refuses any other value.
constexpr int kCloudIoAbiVersion = 1;

// pcl::PCLPointField::PointFieldTypes's values (the plug-in checks them with static_assert).
enum CloudFieldType : uint8_t { kCloudInt32 = 5, kCloudUint32 = 6, kCloudFloat32 = 7 };

// One field of a point: pcl::PCLPointField's members.
struct CloudField {
  std::string name;
  uint32_t offset = 0;  // bytes from the start of the point
  uint8_t datatype = 0;
  uint32_t count = 1;
};

// Points packed as pcl::PCLPointCloud2 holds them: width * height points of point_step bytes.
struct PackedCloud {
  std::vector<CloudField> fields;
  uint32_t width = 0, height = 1, point_step = 0;
  std::vector<uint8_t> data;
};

struct CloudIoTable {
  int abi_version;
  // PCL's writer status (0: written) for `path`; `ply` chooses PLY binary over PCD binary.
  // An exception PCL throws is caught and its message put in `error`.
  int (*write)(const std::string& path, bool ply, const PackedCloud& cloud, std::string& error);
  // PCL's reader status (negative: failed) for `path`, the points in `cloud`.
  int (*read)(const std::string& path, bool ply, PackedCloud& cloud);
};

constexpr const char* kCloudIoPlugin = "lsds_cloud_io.so";
constexpr const char* kCloudIoEntry = "lsds_cloud_io_table";

}  // namespace lsds::pointcloud

// Defined by the plug-in; looked up with dlsym by kCloudIoEntry.
extern "C" const lsds::pointcloud::CloudIoTable* lsds_cloud_io_table();
