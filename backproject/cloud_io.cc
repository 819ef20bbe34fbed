// Point cloud files: the point layout here, PCL's writers and readers in the plug-in
// lsds_cloud_io.so (cloud_io_plugin.cc), opened on first use so that only `lsds backproject`
// loads PCL's io library and VTK.
#include "backproject/cloud_io.h"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "backproject/cloud_io_abi.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/plugin.h"

namespace lsds::pointcloud {

namespace {

using Field = CloudField;

struct FieldSpec {
  const char* name;
  uint8_t datatype;
  size_t offset_in_point;  // offset in CloudPoint
};

// `ids_type`: UINT32 for PCD (pcl::PointXYZRGBL's label), INT32 for PLY
// ("int"): Open3D's tensor PLY reader keeps only uchar, uint16, int, float and
// double properties and silently drops "uint" ones. Same bits either way.
std::vector<FieldSpec> FieldsFor(const Attributes& a, uint8_t ids_type = kCloudUint32) {
  std::vector<FieldSpec> fields = {{"x", kCloudFloat32, offsetof(CloudPoint, x)},
                                   {"y", kCloudFloat32, offsetof(CloudPoint, y)},
                                   {"z", kCloudFloat32, offsetof(CloudPoint, z)}};
  // PCL stores colour as a FLOAT32 field holding the packed bits
  // (pcl::PointXYZRGB::rgb).
  if (a.rgb) fields.push_back({"rgb", kCloudFloat32, offsetof(CloudPoint, rgb)});
  if (a.labels) {
    fields.push_back({"label", ids_type, offsetof(CloudPoint, label)});
    fields.push_back({"instance", ids_type, offsetof(CloudPoint, instance)});
  }
  if (a.normals) {
    fields.push_back({"normal_x", kCloudFloat32, offsetof(CloudPoint, normal_x)});
    fields.push_back({"normal_y", kCloudFloat32, offsetof(CloudPoint, normal_y)});
    fields.push_back({"normal_z", kCloudFloat32, offsetof(CloudPoint, normal_z)});
  }
  return fields;
}

PackedCloud Pack(const PointCloud& cloud, CloudFormat format, PlyIds ply_ids) {
  const bool signed_ids = format == CloudFormat::kPly && ply_ids == PlyIds::kInt;
  const std::vector<FieldSpec> specs =
      FieldsFor(cloud.attributes, signed_ids ? kCloudInt32 : kCloudUint32);
  PackedCloud out;
  uint32_t offset = 0;
  for (const FieldSpec& spec : specs) {
    Field field;
    field.name = spec.name;
    field.offset = offset;
    field.datatype = spec.datatype;
    field.count = 1;
    out.fields.push_back(field);
    offset += 4;
  }
  out.point_step = offset;
  out.width = static_cast<uint32_t>(cloud.points.size());
  out.height = 1;
  out.data.resize(static_cast<size_t>(out.point_step) * out.width);
  uint8_t* dst = out.data.data();
  for (const CloudPoint& p : cloud.points) {
    const auto* src = reinterpret_cast<const uint8_t*>(&p);
    for (const FieldSpec& spec : specs) {
      std::memcpy(dst, src + spec.offset_in_point, 4);
      dst += 4;
    }
  }
  return out;
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

const CloudIoTable& CloudIo() {
  return PluginTable<CloudIoTable>(kCloudIoPlugin, kCloudIoEntry, kCloudIoAbiVersion);
}

}  // namespace

CloudFormat FormatFromPath(const std::filesystem::path& path) {
  const std::string ext = Lower(path.extension().string());
  if (ext == ".pcd") return CloudFormat::kPcd;
  if (ext == ".ply") return CloudFormat::kPly;
  throw Error("unknown point cloud extension '" + path.extension().string() +
                  "'; expected .pcd (PCD binary) or .ply (PLY binary)",
              Location(path.string()));
}

CloudFormat FormatFromName(const std::string& name) {
  const std::string lower = Lower(name);
  if (lower == "pcd") return CloudFormat::kPcd;
  if (lower == "ply") return CloudFormat::kPly;
  throw Error("unknown point cloud format '" + name + "'; expected pcd or ply");
}

const char* Extension(CloudFormat format) { return format == CloudFormat::kPcd ? ".pcd" : ".ply"; }

PlyIds PlyIdsFromName(const std::string& name) {
  if (name == "int") return PlyIds::kInt;
  if (name == "uint") return PlyIds::kUint;
  throw Error("--ply-ids must be int (Open3D) or uint (PCL point types), got '" + name + "'");
}

void WriteCloud(const std::filesystem::path& path,
                const PointCloud& cloud,
                CloudFormat format,
                PlyIds ply_ids) {
  const CloudIoTable& io = CloudIo();
  const PackedCloud packed = Pack(cloud, format, ply_ids);
  // PCL writes by file name and ignores write errors: it writes into memory
  // and the bytes reach `path` through the checked atomic path.
  WriteFileAtomicVia(path, [&](const std::filesystem::path& scratch) {
    std::string detail;
    const int status = io.write(scratch.string(), format == CloudFormat::kPly, packed, detail);
    if (status != 0) {
      throw Error("cannot write point cloud" + (detail.empty() ? std::string() : ": " + detail),
                  Location(path.string()));
    }
  });
}

PointCloud ReadCloud(const std::filesystem::path& path) {
  const CloudFormat format = FormatFromPath(path);
  PackedCloud in;
  const int status = CloudIo().read(path.string(), format == CloudFormat::kPly, in);
  if (status < 0) throw Error("cannot read point cloud", Location(path.string()));
  auto find = [&in](const char* name) -> const Field* {
    for (const Field& f : in.fields)
      if (f.name == name) return &f;
    return nullptr;
  };
  PointCloud cloud;
  cloud.attributes.rgb = find("rgb") != nullptr || find("rgba") != nullptr;
  cloud.attributes.labels = find("label") != nullptr && find("instance") != nullptr;
  cloud.attributes.normals = find("normal_x") != nullptr;
  if (!find("x") || !find("y") || !find("z")) {
    throw Error("point cloud has no x y z fields", Location(path.string()));
  }
  const std::vector<FieldSpec> specs = FieldsFor(cloud.attributes);
  std::vector<const Field*> fields;
  for (const FieldSpec& spec : specs) {
    const Field* f = find(spec.name);
    if (!f && std::strcmp(spec.name, "rgb") == 0) f = find("rgba");
    if (!f || f->count != 1)
      throw Error(std::string("unusable field ") + spec.name, Location(path.string()));
    fields.push_back(f);
  }
  const size_t n = static_cast<size_t>(in.width) * in.height;
  cloud.points.resize(n, CloudPoint{});
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* src = in.data.data() + i * in.point_step;
    auto* dst = reinterpret_cast<uint8_t*>(&cloud.points[i]);
    for (size_t k = 0; k < specs.size(); ++k) {
      std::memcpy(dst + specs[k].offset_in_point, src + fields[k]->offset, 4);
    }
    cloud.points[i].rgb &= 0x00ffffffu;  // PLY readers may fill alpha
  }
  return cloud;
}

}  // namespace lsds::pointcloud
