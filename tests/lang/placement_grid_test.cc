// The placement grid returns every placed footprint that shares ground with a query (a superset
// of the true overlaps, each once, in placement order), at every size.
#include "generator/lang/scene/placement_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace lsds {
namespace {

using Rect = PlacementGrid::Rect;

bool Overlap(const Rect& a, const Rect& b) {
  return a.lo_x <= b.hi_x && b.lo_x <= a.hi_x && a.lo_y <= b.hi_y && b.lo_y <= a.hi_y;
}

Rect RandomRect(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> centre(-100, 100);
  // Mostly clutter, some buildings, a few footprints wider than the grid takes (64 cells).
  std::uniform_real_distribution<double> size(0.1, 3);
  std::uniform_real_distribution<double> big(3, 400);
  const double w = rng() % 10 == 0 ? big(rng) : size(rng);
  const double h = rng() % 10 == 0 ? big(rng) : size(rng);
  const double x = centre(rng), y = centre(rng);
  return {x - w / 2, y - h / 2, x + w / 2, y + h / 2};
}

TEST(PlacementGrid, NearHoldsEveryOverlappingFootprintOnceInOrder) {
  std::mt19937_64 rng(7);
  PlacementGrid grid(4.0);
  std::vector<Rect> placed;
  std::vector<uint32_t> near;
  for (uint32_t i = 0; i < 3000; ++i) {
    const Rect query = RandomRect(rng);
    grid.Near(query, &near);
    EXPECT_TRUE(std::is_sorted(near.begin(), near.end()));
    EXPECT_EQ(std::adjacent_find(near.begin(), near.end()), near.end());
    for (uint32_t j = 0; j < placed.size(); ++j)
      if (Overlap(query, placed[j]))
        EXPECT_TRUE(std::binary_search(near.begin(), near.end(), j)) << i << " misses " << j;
    grid.Insert(i, query);
    placed.push_back(query);
  }
}

TEST(PlacementGrid, NearIsLocalForClutter) {
  PlacementGrid grid(4.0);
  for (uint32_t i = 0; i < 10000; ++i) {
    const double x = (i % 100) * 10.0, y = (i / 100) * 10.0;
    grid.Insert(i, {x, y, x + 1, y + 1});
  }
  std::vector<uint32_t> near;
  grid.Near({500, 500, 501, 501}, &near);
  EXPECT_LE(near.size(), 4u);  // the neighbours, not the field
  EXPECT_NE(std::find(near.begin(), near.end(), 5050u), near.end());
}

TEST(PlacementGrid, FootprintsTheGridCannotHoldAreAlwaysNeighbours) {
  PlacementGrid grid(4.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  grid.Insert(0, {-1e7, -1e7, 1e7, 1e7});  // wider than 64 cells
  grid.Insert(1, {nan, 0, 1, 1});
  grid.Insert(2, {0, 0, inf, 1});
  grid.Insert(3, {1000, 1000, 1001, 1001});
  std::vector<uint32_t> near;
  grid.Near({0, 0, 1, 1}, &near);
  EXPECT_EQ(near, (std::vector<uint32_t>{0, 1, 2}));
  grid.Near({-1e7, -1e7, 1e7, 1e7}, &near);  // a query too wide: everything
  EXPECT_EQ(near, (std::vector<uint32_t>{0, 1, 2, 3}));
}

}  // namespace
}  // namespace lsds
