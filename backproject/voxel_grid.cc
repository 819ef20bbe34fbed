#include "backproject/voxel_grid.h"

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "libs/util/error.h"

namespace lsds::pointcloud {

namespace {

uint64_t Hash(const VoxelKey& k) {
  // Neighbouring cells differ in low bits only: mix them all into the high bits
  // (murmur finalizer).
  uint64_t h = static_cast<uint64_t>(k.x) * 0x9E3779B97F4A7C15ULL +
               static_cast<uint64_t>(k.y) * 0xC2B2AE3D27D4EB4FULL +
               static_cast<uint64_t>(k.z) * 0x165667B19E3779F9ULL;
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDULL;
  h ^= h >> 33;
  h *= 0xC4CEB9FE1A85EC53ULL;
  h ^= h >> 33;
  return h;
}

// Open addressing with linear probing, keys stored in the slots (one cache miss
// per lookup): several times faster than std::unordered_map for millions of
// points.
class KeyIndex {
 public:
  KeyIndex() : slots_(1024) {}
  // The cell index of `key`, or `next` (inserted) when the key is new.
  size_t FindOrInsert(const VoxelKey& key, size_t next) {
    if ((count_ + 1) * 2 > slots_.size()) Grow();
    const size_t mask = slots_.size() - 1;
    for (size_t i = Hash(key) & mask;; i = (i + 1) & mask) {
      Slot& slot = slots_[i];
      if (slot.index == kEmpty) {
        slot.key = key;
        slot.index = next;
        ++count_;
        return next;
      }
      if (slot.key == key) return slot.index;
    }
  }

 private:
  static constexpr size_t kEmpty = ~size_t{0};
  struct Slot {
    VoxelKey key;
    size_t index = kEmpty;
  };
  void Grow() {
    std::vector<Slot> old(slots_.size() * 2);
    old.swap(slots_);
    const size_t mask = slots_.size() - 1;
    for (const Slot& slot : old) {
      if (slot.index == kEmpty) continue;
      size_t i = Hash(slot.key) & mask;
      while (slots_[i].index != kEmpty) i = (i + 1) & mask;
      slots_[i] = slot;
    }
  }
  std::vector<Slot> slots_;
  size_t count_ = 0;
};

// Voxels grouped in blocks of 8x8x8: a block is found by hash, its voxels by
// direct indexing. Consecutive points of an image row fall in the same block,
// so most lookups touch one cached block instead of a random hash slot (the
// accumulation is memory-latency bound otherwise).
class BlockIndex {
 public:
  static constexpr int kShift = 3;
  static constexpr int64_t kMask = (1 << kShift) - 1;
  static constexpr size_t kBlockCells = size_t{1} << (3 * kShift);

  size_t FindOrInsert(const VoxelKey& key, size_t next) {
    // Arithmetic shifts floor negative coordinates too.
    const VoxelKey block{key.x >> kShift, key.y >> kShift, key.z >> kShift};
    if (!(block == last_block_) || cells_.empty()) {
      const size_t count = cells_.size() / kBlockCells;
      last_offset_ = blocks_.FindOrInsert(block, count) * kBlockCells;
      if (last_offset_ == cells_.size()) cells_.resize(cells_.size() + kBlockCells, kEmpty);
      last_block_ = block;
    }
    uint32_t& cell =
        cells_[last_offset_ + static_cast<size_t>(((key.x & kMask) << (2 * kShift)) |
                                                  ((key.y & kMask) << kShift) | (key.z & kMask))];
    if (cell == kEmpty) {
      if (next >= kEmpty) throw Error("--voxel: more than 4 billion voxels");
      cell = static_cast<uint32_t>(next);
    }
    return cell;
  }

 private:
  static constexpr uint32_t kEmpty = ~uint32_t{0};
  KeyIndex blocks_;
  std::vector<uint32_t> cells_;
  VoxelKey last_block_;
  size_t last_offset_ = 0;
};

struct Cell {
  double sum_x = 0, sum_y = 0, sum_z = 0;
  double sum_r = 0, sum_g = 0, sum_b = 0;
  double sum_nx = 0, sum_ny = 0, sum_nz = 0;
  int64_t count = 0;
  double best_centre_distance = INFINITY;
  uint32_t label = 0, instance = 0;
};

// The float nearest `value` that still lies in [lo, hi) of its voxel.
float InsideVoxel(double value, double lo, double hi) {
  float f = static_cast<float>(value);
  while (static_cast<double>(f) >= hi) f = std::nextafter(f, -INFINITY);
  while (static_cast<double>(f) < lo) f = std::nextafter(f, INFINITY);
  return f;
}

}  // namespace

struct VoxelAccumulator::Impl {
  double size;
  Attributes attributes;
  BlockIndex index;
  std::vector<VoxelKey> keys;
  std::vector<Cell> cells;
};

VoxelAccumulator::VoxelAccumulator(double size, Attributes attributes) : impl_(new Impl) {
  if (!(size > 0) || !std::isfinite(size)) throw Error("voxel size must be a positive number");
  impl_->size = size;
  impl_->attributes = attributes;
}

VoxelAccumulator::~VoxelAccumulator() = default;

size_t VoxelAccumulator::voxel_count() const { return impl_->cells.size(); }

void VoxelAccumulator::Add(const PointCloud& cloud) {
  Impl& s = *impl_;
  VoxelKey last_key{INT64_MIN, 0, 0};
  size_t index = 0;
  for (const CloudPoint& p : cloud.points) {
    // Neighbouring pixels often share a voxel: skip the lookup then.
    const VoxelKey key = VoxelOf(p.x, p.y, p.z, s.size);
    if (!(key == last_key)) index = s.index.FindOrInsert(key, s.cells.size());
    last_key = key;
    if (index == s.cells.size()) {
      s.cells.emplace_back();
      s.keys.push_back(key);
    }
    Cell& c = s.cells[index];
    c.sum_x += p.x;
    c.sum_y += p.y;
    c.sum_z += p.z;
    ++c.count;
    if (s.attributes.rgb) {
      c.sum_r += (p.rgb >> 16) & 0xff;
      c.sum_g += (p.rgb >> 8) & 0xff;
      c.sum_b += p.rgb & 0xff;
    }
    if (s.attributes.normals) {
      c.sum_nx += p.normal_x;
      c.sum_ny += p.normal_y;
      c.sum_nz += p.normal_z;
    }
    if (s.attributes.labels) {
      const double dx = p.x - (key.x + 0.5) * s.size, dy = p.y - (key.y + 0.5) * s.size,
                   dz = p.z - (key.z + 0.5) * s.size;
      const double d = dx * dx + dy * dy + dz * dz;
      if (d < c.best_centre_distance) {
        c.best_centre_distance = d;
        c.label = p.label;
        c.instance = p.instance;
      }
    }
  }
}

PointCloud VoxelAccumulator::Finish() const {
  const Impl& s = *impl_;
  PointCloud out;
  out.attributes = s.attributes;
  out.points.resize(s.cells.size(), CloudPoint{});
  for (size_t i = 0; i < s.cells.size(); ++i) {
    const Cell& c = s.cells[i];
    const VoxelKey& k = s.keys[i];
    const double n = static_cast<double>(c.count);
    CloudPoint& p = out.points[i];
    p.x = InsideVoxel(c.sum_x / n, k.x * s.size, (k.x + 1) * s.size);
    p.y = InsideVoxel(c.sum_y / n, k.y * s.size, (k.y + 1) * s.size);
    p.z = InsideVoxel(c.sum_z / n, k.z * s.size, (k.z + 1) * s.size);
    // Guard the definition used by VoxelOf (float division) as well as the
    // double bounds above.
    while (VoxelOf(p.x, p.y, p.z, s.size).x > k.x) p.x = std::nextafter(p.x, -INFINITY);
    while (VoxelOf(p.x, p.y, p.z, s.size).x < k.x) p.x = std::nextafter(p.x, INFINITY);
    while (VoxelOf(p.x, p.y, p.z, s.size).y > k.y) p.y = std::nextafter(p.y, -INFINITY);
    while (VoxelOf(p.x, p.y, p.z, s.size).y < k.y) p.y = std::nextafter(p.y, INFINITY);
    while (VoxelOf(p.x, p.y, p.z, s.size).z > k.z) p.z = std::nextafter(p.z, -INFINITY);
    while (VoxelOf(p.x, p.y, p.z, s.size).z < k.z) p.z = std::nextafter(p.z, INFINITY);
    if (s.attributes.rgb) {
      auto mean = [n](double sum) { return static_cast<uint8_t>(std::lround(sum / n)); };
      p.rgb = PackRgb(mean(c.sum_r), mean(c.sum_g), mean(c.sum_b));
    }
    if (s.attributes.normals) {
      Eigen::Vector3d normal(c.sum_nx, c.sum_ny, c.sum_nz);
      if (normal.norm() > 0) normal.normalize();
      p.normal_x = static_cast<float>(normal.x());
      p.normal_y = static_cast<float>(normal.y());
      p.normal_z = static_cast<float>(normal.z());
    }
    p.label = c.label;
    p.instance = c.instance;
  }
  return out;
}

}  // namespace lsds::pointcloud
