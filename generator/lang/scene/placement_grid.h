// A grid over the ground of the objects placed so far, for the overlap test of the next one.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace lsds {

// The placed objects' footprints (x-y boxes, already grown by their separation) by the grid
// cells they cover, so that a new object is tested against its neighbours only: placing n objects
// costs about n tests instead of n^2 / 2 (10^5 bushes plan in seconds, not minutes). A footprint
// that would span more than kMaxCellsPerAxis cells on an axis (a building among pebbles, anything
// unbounded) goes on a short list that every query returns instead.
class PlacementGrid {
 public:
  struct Rect {
    double lo_x, lo_y, hi_x, hi_y;
  };
  static constexpr int64_t kMaxCellsPerAxis = 64;

  explicit PlacementGrid(double cell_m) : cell_m_(cell_m) {}

  void Insert(uint32_t index, const Rect& footprint);

  // The indices whose footprints may share ground with `footprint`: each once, in ascending
  // order (the order in which they were placed).
  void Near(const Rect& footprint, std::vector<uint32_t>* out) const;

 private:
  struct CellRange {
    int64_t x0, y0, x1, y1;
  };
  // False when the footprint is too large or not finite for the grid.
  bool CellsOf(const Rect& footprint, CellRange* range) const;
  static uint64_t Key(int64_t x, int64_t y) {
    return (static_cast<uint64_t>(x) << 32) ^ (static_cast<uint64_t>(y) & 0xffffffffu);
  }

  double cell_m_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
  std::vector<uint32_t> large_;
};

}  // namespace lsds
