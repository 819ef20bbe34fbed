// PCD and PLY files: what is written reads back equal, with lsds and with PCL's
// own point types.
#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include "libs/pointcloud/cloud_io.h"
#include "libs/util/error.h"
#include "tests/backproject/test_util.h"

namespace lsds::pointcloud {
namespace {

namespace fs = std::filesystem;

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
      p.normal_x = coord(rng) / 100, p.normal_y = coord(rng) / 100,
      p.normal_z = 1;
    cloud.points.push_back(p);
  }
  return cloud;
}

void ExpectEqual(const PointCloud& a, const PointCloud& b) {
  ASSERT_TRUE(a.attributes == b.attributes);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    ASSERT_EQ(std::memcmp(&a.points[i], &b.points[i], sizeof(CloudPoint)), 0)
        << "point " << i;
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

TEST(CloudIo, UnknownExtensionAndUnwritablePathsAreClearErrors) {
  testing::ScratchDir dir("io_bad");
  EXPECT_THROW(FormatFromPath("cloud.xyz"), Error);
  EXPECT_THROW(FormatFromPath("cloud"), Error);
  EXPECT_THROW(FormatFromName("las"), Error);
  try {
    WriteCloud(dir / "missing" / "c.pcd", PointCloud{}, CloudFormat::kPcd);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing/c.pcd"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(testing::ListDir(dir.path()), "");
}

}  // namespace
}  // namespace lsds::pointcloud
