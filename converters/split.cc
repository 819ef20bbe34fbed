#include "converters/split.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "libs/util/error.h"
#include "libs/util/splitmix64.h"
#include "libs/util/strings.h"

namespace lsds::convert {

std::vector<SplitPart> ParseSplit(const std::string& spec) {
  std::vector<SplitPart> parts;
  double sum = 0;
  const Location where("--split");
  for (const std::string& entry : Split(spec, ',')) {
    const size_t eq = entry.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw Error("expected NAME=FRACTION, got '" + entry + "'", where);
    }
    SplitPart part;
    part.name = entry.substr(0, eq);
    for (char c : part.name) {
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) {
        throw Error("split name '" + part.name + "' may only hold letters, digits, '_' and '-'",
                    where);
      }
    }
    const std::string value = entry.substr(eq + 1);
    char* end = nullptr;
    part.fraction = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !(part.fraction >= 0) || !std::isfinite(part.fraction)) {
      throw Error("bad fraction '" + value + "' for split '" + part.name + "'", where);
    }
    for (const SplitPart& other : parts) {
      if (other.name == part.name) throw Error("split '" + part.name + "' given twice", where);
    }
    sum += part.fraction;
    parts.push_back(part);
  }
  if (parts.empty()) throw Error("no split given", where);
  if (std::abs(sum - 1.0) > 1e-6) {
    throw Error("split fractions sum to " + std::to_string(sum) + ", not 1", where);
  }
  return parts;
}

uint64_t Fnv1a64(const std::string& text) {
  uint64_t hash = 14695981039346656037ull;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

std::string SplitGroup(const Frame& frame, int64_t block) {
  if (!frame.sequence.empty()) return frame.sequence;
  return "#frames/" + std::to_string(frame.index / block);
}

namespace {

// Sorts (frame index, split) entries by index; of a repeated index (a
// collection that repeats a frame) the last entry counts, as in a map.
void SortByIndexKeepLast(std::vector<std::pair<int64_t, uint32_t>>* entries) {
  std::stable_sort(entries->begin(), entries->end(), [](const auto& a, const auto& b) {
    return a.first < b.first;
  });
  std::vector<std::pair<int64_t, uint32_t>>& e = *entries;
  size_t kept = 0;
  for (size_t i = 0; i < e.size(); ++i) {
    if (kept > 0 && e[kept - 1].first == e[i].first)
      e[kept - 1] = e[i];
    else
      e[kept++] = e[i];
  }
  e.resize(kept);
}

}  // namespace

size_t AssignSplitIndex(const std::vector<SplitPart>& parts, const std::string& group) {
  const double u = static_cast<double>(Mix64(Fnv1a64(group)) >> 11) * 0x1.0p-53;
  double cumulative = 0;
  for (size_t i = 0; i < parts.size(); ++i) {
    cumulative += parts[i].fraction;
    if (u < cumulative) return i;
  }
  // Rounding of the sum: the last part with a non-zero share.
  for (size_t i = parts.size(); i-- > 0;) {
    if (parts[i].fraction > 0) return i;
  }
  return parts.size() - 1;
}

const std::string& AssignSplit(const std::vector<SplitPart>& parts, const std::string& group) {
  return parts[AssignSplitIndex(parts, group)].name;
}

const std::string& SplitPlan::SplitOf(int64_t index) const {
  const auto it = std::lower_bound(
      split_of_frame.begin(),
      split_of_frame.end(),
      index,
      [](const std::pair<int64_t, uint32_t>& entry, int64_t i) { return entry.first < i; });
  if (it == split_of_frame.end() || it->first != index)
    throw std::out_of_range("frame " + std::to_string(index) + " has no planned split");
  return names[it->second];
}

SplitPlan PlanSplits(const std::vector<SplitPart>& parts, const std::vector<SplitFrame>& frames) {
  SplitPlan plan;
  for (const SplitPart& part : parts) plan.names.push_back(part.name);
  std::vector<int64_t> filled(parts.size(), 0);
  plan.split_of_frame.reserve(frames.size());
  for (const SplitFrame& f : frames) {
    const size_t split = AssignSplitIndex(parts, f.group);
    plan.split_of_frame.emplace_back(f.index, static_cast<uint32_t>(split));
    ++filled[split];
  }
  SortByIndexKeepLast(&plan.split_of_frame);
  std::vector<size_t> wanted;  // positions of the parts with a non-zero share
  for (size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].fraction > 0) wanted.push_back(i);
  }
  const bool all_filled =
      std::all_of(wanted.begin(), wanted.end(), [&](size_t i) { return filled[i] > 0; });
  if (all_filled || frames.empty()) return plan;

  const int64_t n = static_cast<int64_t>(frames.size());
  const int64_t k = static_cast<int64_t>(wanted.size());
  if (n < k) {
    throw Error("cannot fill split '" + parts[wanted[n]].name + "': " + std::to_string(n) +
                    " frame(s) for " + std::to_string(k) + " splits with a non-zero fraction",
                Location("--split"));
  }
  // Block sizes: rounded cumulative fractions, then each at least one frame
  // (taken from the largest block).
  std::vector<int64_t> size(k);
  double cumulative = 0, total = 0;
  for (size_t i : wanted) total += parts[i].fraction;
  int64_t start = 0;
  for (int64_t i = 0; i < k; ++i) {
    cumulative += parts[wanted[i]].fraction / total;
    const int64_t end = i + 1 == k ? n : std::llround(cumulative * n);
    size[i] = std::max<int64_t>(0, end - start);
    start += size[i];
  }
  for (int64_t i = 0; i < k; ++i) {
    while (size[i] == 0) {
      const auto largest = std::max_element(size.begin(), size.end());
      --*largest;
      ++size[i];
    }
  }
  std::vector<SplitFrame> ordered = frames;
  std::stable_sort(ordered.begin(), ordered.end(), [](const SplitFrame& a, const SplitFrame& b) {
    return a.group != b.group ? a.group < b.group : a.index < b.index;
  });
  std::vector<std::pair<int64_t, uint32_t>> blocks;
  blocks.reserve(ordered.size());
  int64_t at = 0;
  for (int64_t i = 0; i < k; ++i) {
    for (int64_t j = 0; j < size[i]; ++j)
      blocks.emplace_back(ordered[at++].index, static_cast<uint32_t>(wanted[i]));
  }
  SortByIndexKeepLast(&blocks);
  plan.split_of_frame = std::move(blocks);
  plan.blocks = true;
  return plan;
}

}  // namespace lsds::convert
