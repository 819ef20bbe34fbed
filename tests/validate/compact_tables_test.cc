// The sorted-vector tables of `lsds validate`'s streaming state: the same
// answers as a hash set and a map, with memory bounded by distinct entries.
#include "validators/compact_tables.h"

#include <cstdint>
#include <unordered_set>

#include <gtest/gtest.h>

namespace lsds::validate {
namespace {

TEST(HashSet64, AnswersAsASetAndKeepsOneCopyOfRepeatedValues) {
  HashSet64 set;
  std::unordered_set<uint64_t> reference;
  // A million frames naming the same nine files, then 5000 distinct ones.
  for (int frame = 0; frame < 1000000; ++frame) set.Insert(static_cast<uint64_t>(frame % 9) * 977);
  for (uint64_t v = 0; v < 9; ++v) reference.insert(v * 977);
  for (uint64_t v = 1; v <= 5000; ++v) {
    set.Insert(v * 0x9E3779B97F4A7C15ull);
    reference.insert(v * 0x9E3779B97F4A7C15ull);
  }
  for (uint64_t v : reference) EXPECT_TRUE(set.Contains(v)) << v;
  EXPECT_FALSE(set.Contains(1));
  EXPECT_FALSE(set.Contains(978));
  EXPECT_EQ(set.size(), reference.size());
}

TEST(FrameTable, LastValueOfAnIndexCountsAndEachIsTakenOnce) {
  FrameTable<int> table;
  table.Add(7, 70);
  table.Add(3, 30);
  table.Add(7, 71);  // metadata.json names frame 7 twice: the last counts
  table.Add(-2, -20);
  const int* seven = table.Take(7);
  ASSERT_NE(seven, nullptr);
  EXPECT_EQ(*seven, 71);
  EXPECT_EQ(table.Take(7), nullptr);  // a duplicate frame 7 in collection.json finds nothing
  ASSERT_NE(table.Take(-2), nullptr);
  EXPECT_EQ(*table.Take(3), 30);
  EXPECT_EQ(table.Take(4), nullptr);
  EXPECT_EQ(table.Take(100), nullptr);
}

}  // namespace
}  // namespace lsds::validate
