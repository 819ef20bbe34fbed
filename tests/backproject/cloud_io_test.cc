// PCD and PLY files: what is written reads back equal, with lsds and with PCL's
// own point types.
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include "backproject/cloud_io.h"
#include "libs/util/error.h"
#include "tests/backproject/test_util.h"

namespace lsds::pointcloud {
namespace {

namespace fs = std::filesystem;

std::string ReadFileText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

PointCloud RandomCloud(size_t n, Attributes attributes) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-100, 100);
  std::uniform_int_distribution<uint32_t> id(0, 5000);
  PointCloud cloud;
  cloud.attributes = attributes;
  for (size_t i = 0; i < n; ++i) {
    CloudPoint p{};
    p.x = coord(rng), p.y = coord(rng), p.z = coord(rng);
    if (attributes.rgb) p.rgb = id(rng) * 3355 & 0xffffff;
    if (attributes.labels) p.label = id(rng), p.instance = id(rng) * 1000;
    if (attributes.normals)
      p.normal_x = coord(rng) / 100, p.normal_y = coord(rng) / 100, p.normal_z = 1;
    cloud.points.push_back(p);
  }
  return cloud;
}

void ExpectEqual(const PointCloud& a, const PointCloud& b) {
  ASSERT_TRUE(a.attributes == b.attributes);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    ASSERT_EQ(std::memcmp(&a.points[i], &b.points[i], sizeof(CloudPoint)), 0) << "point " << i;
  }
}

TEST(CloudIo, PcdAndPlyReadBackEqualToWhatWasWritten) {
  testing::ScratchDir dir("io");
  for (const Attributes attributes : {Attributes{},
                                      Attributes{true, true, false},
                                      Attributes{true, true, true},
                                      Attributes{false, false, true}}) {
    const PointCloud cloud = RandomCloud(1000, attributes);
    for (const char* name : {"c.pcd", "c.ply", "C.PLY"}) {
      WriteCloud(dir / name, cloud, FormatFromPath(name));
      ExpectEqual(cloud, ReadCloud(dir / name));
    }
  }
  // An empty cloud is a valid file too.
  WriteCloud(dir / "empty.pcd", PointCloud{}, CloudFormat::kPcd);
  EXPECT_TRUE(ReadCloud(dir / "empty.pcd").points.empty());
}

TEST(CloudIo, PclPointTypesReadTheFiles) {
  testing::ScratchDir dir("pcl");
  const PointCloud cloud = RandomCloud(500, Attributes{true, true, true});
  WriteCloud(dir / "c.pcd", cloud, CloudFormat::kPcd);
  WriteCloud(dir / "c.ply", cloud, CloudFormat::kPly);

  pcl::PointCloud<pcl::PointXYZRGBL> labelled;
  ASSERT_EQ(pcl::io::loadPCDFile(dir / "c.pcd", labelled), 0);
  ASSERT_EQ(labelled.size(), cloud.points.size());
  for (size_t i = 0; i < labelled.size(); ++i) {
    const CloudPoint& p = cloud.points[i];
    ASSERT_EQ(labelled[i].x, p.x);
    ASSERT_EQ(labelled[i].y, p.y);
    ASSERT_EQ(labelled[i].z, p.z);
    ASSERT_EQ(labelled[i].rgba & 0xffffffu, p.rgb);
    ASSERT_EQ(labelled[i].label, p.label);
  }
  pcl::PointCloud<pcl::PointXYZRGBNormal> normals;
  ASSERT_EQ(pcl::io::loadPLYFile(dir / "c.ply", normals), 0);
  ASSERT_EQ(normals.size(), cloud.points.size());
  for (size_t i = 0; i < normals.size(); ++i) {
    const CloudPoint& p = cloud.points[i];
    ASSERT_EQ(normals[i].x, p.x);
    ASSERT_EQ(normals[i].r, (p.rgb >> 16) & 0xff);
    ASSERT_EQ(normals[i].g, (p.rgb >> 8) & 0xff);
    ASSERT_EQ(normals[i].b, p.rgb & 0xff);
    ASSERT_EQ(normals[i].normal_x, p.normal_x);
    ASSERT_EQ(normals[i].normal_z, p.normal_z);
  }
}

// The PLY header up to end_header.
std::string PlyHeader(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string header, line;
  while (std::getline(in, line) && line != "end_header") header += line + "\n";
  return header;
}

// A labelled cloud whose ids include one above 2^31 (written as the int32 with
// the same bits).
PointCloud LabelledCloud() {
  PointCloud cloud = RandomCloud(300, Attributes{true, true, false});
  cloud.points[7].instance = 3000000000u;
  return cloud;
}

TEST(CloudIo, PlyIdsAreIntPropertiesThatPclKeeps) {
  testing::ScratchDir dir("ply_ids");
  const PointCloud cloud = LabelledCloud();
  WriteCloud(dir / "c.ply", cloud, CloudFormat::kPly);
  // "int", which Open3D's tensor reader keeps, not "uint", which it drops.
  const std::string header = PlyHeader(dir / "c.ply");
  EXPECT_NE(header.find("property int label\n"), std::string::npos) << header;
  EXPECT_NE(header.find("property int instance\n"), std::string::npos);
  EXPECT_EQ(header.find("uint"), std::string::npos) << header;
  // PCL's own PLY reader keeps both properties, value for value.
  pcl::PCLPointCloud2 blob;
  ASSERT_EQ(pcl::io::loadPLYFile((dir / "c.ply").string(), blob), 0);
  ASSERT_EQ(blob.width * blob.height, cloud.points.size());
  for (const char* name : {"label", "instance"}) {
    const pcl::PCLPointField* field = nullptr;
    for (const pcl::PCLPointField& f : blob.fields)
      if (f.name == name) field = &f;
    ASSERT_NE(field, nullptr) << name;
    EXPECT_EQ(field->datatype, pcl::PCLPointField::INT32);
    for (size_t i = 0; i < cloud.points.size(); ++i) {
      uint32_t bits;
      std::memcpy(&bits, blob.data.data() + i * blob.point_step + field->offset, 4);
      ASSERT_EQ(bits,
                std::string(name) == "label" ? cloud.points[i].label : cloud.points[i].instance)
          << name << " point " << i;
    }
  }
  // PCD keeps uint32 (pcl::PointXYZRGBL's label type).
  WriteCloud(dir / "c.pcd", cloud, CloudFormat::kPcd);
  EXPECT_NE(ReadFileText(dir / "c.pcd").find("TYPE F F F F U U"), std::string::npos);
}

// --ply-ids uint: the type pcl::PointXYZRGBL's label has, so PCL's typed reader fills it.
TEST(CloudIo, UintPlyIdsAreReadByPclPointTypes) {
  testing::ScratchDir dir("ply_uint");
  const PointCloud cloud = LabelledCloud();
  WriteCloud(dir / "c.ply", cloud, CloudFormat::kPly, PlyIds::kUint);
  const std::string header = PlyHeader(dir / "c.ply");
  EXPECT_NE(header.find("property uint label\n"), std::string::npos) << header;
  pcl::PointCloud<pcl::PointXYZRGBL> labelled;
  ASSERT_EQ(pcl::io::loadPLYFile((dir / "c.ply").string(), labelled), 0);
  ASSERT_EQ(labelled.size(), cloud.points.size());
  for (size_t i = 0; i < cloud.points.size(); ++i)
    ASSERT_EQ(labelled[i].label, cloud.points[i].label) << i;
  // With the default int ids the same typed read loses them: why the flag exists.
  WriteCloud(dir / "d.ply", cloud, CloudFormat::kPly);
  pcl::PointCloud<pcl::PointXYZRGBL> dropped;
  ASSERT_EQ(pcl::io::loadPLYFile((dir / "d.ply").string(), dropped), 0);
  size_t kept = 0;
  for (size_t i = 0; i < cloud.points.size(); ++i)
    kept += dropped[i].label == cloud.points[i].label && cloud.points[i].label != 0;
  EXPECT_EQ(kept, 0u);
  EXPECT_EQ(PlyIdsFromName("uint"), PlyIds::kUint);
  EXPECT_THROW(PlyIdsFromName("u32"), Error);
}

TEST(CloudIo, Open3dTensorReaderKeepsPlyLabels) {
  // Debian's python3 with python3-open3d (scripts/install-deps.sh --bench).
  const std::string python = "/usr/bin/python3";
  std::string out;
  if (std::system((python + " -c 'import open3d' >/dev/null 2>&1").c_str()) != 0) {
    GTEST_SKIP() << "python3-open3d is not installed (scripts/install-deps.sh "
                    "--bench installs it); PCL's reader is tested always";
  }
  testing::ScratchDir dir("ply_open3d");
  const PointCloud cloud = LabelledCloud();
  WriteCloud(dir / "c.ply", cloud, CloudFormat::kPly);
  std::ofstream(dir / "read.py") << "import sys, numpy as np, open3d as o3d\n"
                                    "pc = o3d.t.io.read_point_cloud(sys.argv[1])\n"
                                    "for name in ('label', 'instance'):\n"
                                    "    a = pc.point[name].numpy().reshape(-1)\n"
                                    "    print(name, a.dtype)\n"
                                    "    a.astype(np.int32).tofile(sys.argv[1] + '.' + name)\n";
  ASSERT_EQ(std::system((python + " " + (dir / "read.py").string() + " " +
                         (dir / "c.ply").string() + " > " + (dir / "log").string() + " 2>&1")
                            .c_str()),
            0)
      << ReadFileText(dir / "log");
  EXPECT_NE(ReadFileText(dir / "log").find("label int32"), std::string::npos)
      << ReadFileText(dir / "log");
  for (const char* name : {"label", "instance"}) {
    const std::string bytes = ReadFileText(dir / (std::string("c.ply.") + name));
    ASSERT_EQ(bytes.size(), cloud.points.size() * 4) << name;
    for (size_t i = 0; i < cloud.points.size(); ++i) {
      uint32_t bits;
      std::memcpy(&bits, bytes.data() + 4 * i, 4);
      ASSERT_EQ(bits,
                std::string(name) == "label" ? cloud.points[i].label : cloud.points[i].instance)
          << name << " point " << i;
    }
  }
}

TEST(CloudIo, UnknownExtensionAndUnwritablePathsAreClearErrors) {
  testing::ScratchDir dir("io_bad");
  EXPECT_THROW(FormatFromPath("cloud.xyz"), Error);
  EXPECT_THROW(FormatFromPath("cloud"), Error);
  EXPECT_THROW(FormatFromName("las"), Error);
  try {
    WriteCloud(dir / "missing" / "c.pcd", PointCloud{}, CloudFormat::kPcd);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing/c.pcd"), std::string::npos) << e.what();
  }
  EXPECT_EQ(testing::ListDir(dir.path()), "");
}

}  // namespace
}  // namespace lsds::pointcloud
