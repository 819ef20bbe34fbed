// A point cloud in memory, free of PCL so that any code may include it. The
// files are written with PCL (cloud_io.h) using PCL's field names: x y z, rgb
// (packed 0x00RRGGBB as in pcl::PointXYZRGB), label (the class id, as in
// pcl::PointXYZRGBL), instance, normal_x normal_y normal_z.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <utility>
#include <vector>

namespace lsds::pointcloud {

// Trivial on purpose (no member initializers): clouds of millions of points
// are allocated without zero-filling them first. `CloudPoint{}` is all zeros.
struct CloudPoint {
  float x, y, z;
  uint32_t rgb;       // 0x00RRGGBB, sRGB 8 bit
  uint32_t label;     // class id, 0 background
  uint32_t instance;  // instance id, 0 background
  float normal_x, normal_y, normal_z;
};

// Large point buffers get transparent huge pages (one page fault per 2 MB
// instead of per 4 KB: the faults cost more than the back-projection itself).
void* AllocatePointMemory(size_t bytes);
void FreePointMemory(void* memory);

// std::allocator semantics, but resize() leaves new points uninitialized
// (default-initialization) and big buffers use huge pages.
template <typename T>
struct PointAllocator {
  using value_type = T;
  PointAllocator() = default;
  template <typename U>
  PointAllocator(const PointAllocator<U>&) {}  // NOLINT: rebinding
  T* allocate(size_t n) { return static_cast<T*>(AllocatePointMemory(n * sizeof(T))); }
  void deallocate(T* p, size_t) { FreePointMemory(p); }
  template <typename U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <typename U>
  bool operator==(const PointAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const PointAllocator<U>&) const {
    return false;
  }
};

using PointVector = std::vector<CloudPoint, PointAllocator<CloudPoint>>;

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
  PointVector points;
};

inline uint32_t PackRgb(uint8_t r, uint8_t g, uint8_t b) {
  return (uint32_t{r} << 16) | (uint32_t{g} << 8) | uint32_t{b};
}

}  // namespace lsds::pointcloud
