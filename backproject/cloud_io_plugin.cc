// The point-cloud-files plug-in: PCL's PCD and PLY writers and readers over the packed points of
// cloud_io_abi.h, and nothing else. The only PCL includes of lsds (PCL is heavy to compile and its
// io library loads VTK: keep it here). Built as a CMake MODULE, opened by cloud_io.cc on first use.
#include <exception>

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include "backproject/cloud_io_abi.h"

namespace {

using lsds::pointcloud::CloudField;
using lsds::pointcloud::PackedCloud;

static_assert(lsds::pointcloud::kCloudInt32 == pcl::PCLPointField::INT32);
static_assert(lsds::pointcloud::kCloudUint32 == pcl::PCLPointField::UINT32);
static_assert(lsds::pointcloud::kCloudFloat32 == pcl::PCLPointField::FLOAT32);

// PCL prints its own errors to stderr; lsds's name the file instead.
struct QuietPcl {
  QuietPcl() : previous(pcl::console::getVerbosityLevel()) {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  ~QuietPcl() { pcl::console::setVerbosityLevel(previous); }
  QuietPcl(const QuietPcl&) = delete;
  QuietPcl& operator=(const QuietPcl&) = delete;
  pcl::console::VERBOSITY_LEVEL previous;
};

int Write(const std::string& path, bool ply, const PackedCloud& cloud, std::string& error) {
  pcl::PCLPointCloud2 out;
  for (const CloudField& f : cloud.fields) {
    pcl::PCLPointField field;
    field.name = f.name;
    field.offset = f.offset;
    field.datatype = f.datatype;
    field.count = f.count;
    out.fields.push_back(field);
  }
  out.point_step = cloud.point_step;
  out.width = cloud.width;
  out.height = cloud.height;
  out.row_step = out.point_step * out.width;
  out.is_dense = true;
  out.data = cloud.data;
  const QuietPcl quiet;
  try {
    if (!ply) return pcl::PCDWriter().writeBinary(path, out);
    return pcl::PLYWriter().writeBinary(
        path, out, Eigen::Vector4f::Zero(), Eigen::Quaternionf::Identity(), /*use_camera=*/false);
  } catch (const std::exception& e) {
    error = e.what();
    return -1;
  }
}

int Read(const std::string& path, bool ply, PackedCloud& cloud) {
  pcl::PCLPointCloud2 in;
  int status = -1;
  {
    const QuietPcl quiet;
    try {
      status = ply ? pcl::io::loadPLYFile(path, in) : pcl::io::loadPCDFile(path, in);
    } catch (const std::exception&) {
      status = -1;
    }
  }
  if (status < 0) return status;
  cloud.fields.clear();
  for (const pcl::PCLPointField& f : in.fields)
    cloud.fields.push_back({f.name, f.offset, f.datatype, f.count});
  cloud.width = in.width;
  cloud.height = in.height;
  cloud.point_step = in.point_step;
  cloud.data = std::move(in.data);
  return status;
}

const lsds::pointcloud::CloudIoTable kTable = {lsds::pointcloud::kCloudIoAbiVersion, Write, Read};

}  // namespace

extern "C" __attribute__((visibility("default"))) const lsds::pointcloud::CloudIoTable*
lsds_cloud_io_table() {
  return &kTable;
}
