// A point cloud in memory, free of PCL so that any code may include it. The
// files are written with PCL (cloud_io.h) using PCL's field names: x y z, rgb
// (packed 0x00RRGGBB as in pcl::PointXYZRGB), label (the class id, as in
// pcl::PointXYZRGBL), instance, normal_x normal_y normal_z.
#pragma once

#include <cstdint>
#include <vector>

namespace lsds::pointcloud {

struct CloudPoint {
  float x = 0, y = 0, z = 0;
  uint32_t rgb = 0;       // 0x00RRGGBB, sRGB 8 bit
  uint32_t label = 0;     // class id, 0 background
  uint32_t instance = 0;  // instance id, 0 background
  float normal_x = 0, normal_y = 0, normal_z = 0;
};

// Which attributes the points carry (and the files hold). Position is always
// there.
struct Attributes {
  bool rgb = false;
  bool labels = false;  // label + instance
  bool normals = false;
  bool operator==(const Attributes& o) const {
    return rgb == o.rgb && labels == o.labels && normals == o.normals;
  }
};

struct PointCloud {
  Attributes attributes;
  std::vector<CloudPoint> points;
};

inline uint32_t PackRgb(uint8_t r, uint8_t g, uint8_t b) {
  return (uint32_t{r} << 16) | (uint32_t{g} << 8) | uint32_t{b};
}

}  // namespace lsds::pointcloud
