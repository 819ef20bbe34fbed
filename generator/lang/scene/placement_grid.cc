#include "generator/lang/scene/placement_grid.h"

#include <algorithm>
#include <cmath>

namespace lsds {

bool PlacementGrid::CellsOf(const Rect& r, CellRange* range) const {
  const double lo_x = std::floor(r.lo_x / cell_m_), lo_y = std::floor(r.lo_y / cell_m_);
  const double hi_x = std::floor(r.hi_x / cell_m_), hi_y = std::floor(r.hi_y / cell_m_);
  // Written so that NaN and infinities fail too.
  if (!(hi_x - lo_x < kMaxCellsPerAxis && hi_y - lo_y < kMaxCellsPerAxis)) return false;
  // Cells are keyed by 32-bit coordinates: far beyond any terrain (2^31 cells of metres).
  constexpr double kLimit = 2e9;
  if (!(std::abs(lo_x) < kLimit && std::abs(lo_y) < kLimit && std::abs(hi_x) < kLimit &&
        std::abs(hi_y) < kLimit))
    return false;
  *range = {static_cast<int64_t>(lo_x),
            static_cast<int64_t>(lo_y),
            static_cast<int64_t>(hi_x),
            static_cast<int64_t>(hi_y)};
  return true;
}

void PlacementGrid::Insert(uint32_t index, const Rect& footprint) {
  CellRange c;
  if (!CellsOf(footprint, &c)) {
    large_.push_back(index);
    return;
  }
  for (int64_t x = c.x0; x <= c.x1; ++x)
    for (int64_t y = c.y0; y <= c.y1; ++y) cells_[Key(x, y)].push_back(index);
}

void PlacementGrid::Near(const Rect& footprint, std::vector<uint32_t>* out) const {
  out->clear();
  CellRange c;
  if (!CellsOf(footprint, &c)) {
    // A query too large for the grid: every footprint is a neighbour.
    for (const auto& [key, indices] : cells_)
      out->insert(out->end(), indices.begin(), indices.end());
  } else {
    for (int64_t x = c.x0; x <= c.x1; ++x)
      for (int64_t y = c.y0; y <= c.y1; ++y) {
        const auto it = cells_.find(Key(x, y));
        if (it != cells_.end()) out->insert(out->end(), it->second.begin(), it->second.end());
      }
  }
  out->insert(out->end(), large_.begin(), large_.end());
  std::sort(out->begin(), out->end());
  out->erase(std::unique(out->begin(), out->end()), out->end());
}

}  // namespace lsds
