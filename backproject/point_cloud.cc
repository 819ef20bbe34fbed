#include "backproject/point_cloud.h"

#include <sys/mman.h>

#include <cstdlib>
#include <new>

namespace lsds::pointcloud {

namespace {
constexpr size_t kHugePage = size_t{2} << 20;
constexpr size_t kHugeThreshold = size_t{8} << 20;
}  // namespace

void* AllocatePointMemory(size_t bytes) {
  if (bytes >= kHugeThreshold) {
    const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* memory = std::aligned_alloc(kHugePage, rounded);
    if (memory == nullptr) throw std::bad_alloc();
    ::madvise(memory, rounded, MADV_HUGEPAGE);  // a hint: failure is harmless
    return memory;
  }
  void* memory = std::malloc(bytes == 0 ? 1 : bytes);
  if (memory == nullptr) throw std::bad_alloc();
  return memory;
}

void FreePointMemory(void* memory) { std::free(memory); }

}  // namespace lsds::pointcloud
