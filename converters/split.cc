#include "converters/split.h"

#include <algorithm>
#include <cmath>

#include <cmath>
#include <cstdlib>

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

const std::string& AssignSplit(const std::vector<SplitPart>& parts, const std::string& group) {
  const double u = static_cast<double>(Mix64(Fnv1a64(group)) >> 11) * 0x1.0p-53;
  double cumulative = 0;
  for (const SplitPart& part : parts) {
    cumulative += part.fraction;
    if (u < cumulative) return part.name;
  }
  // Rounding of the sum: the last part with a non-zero share.
  for (auto it = parts.rbegin(); it != parts.rend(); ++it) {
    if (it->fraction > 0) return it->name;
  }
  return parts.back().name;
}

SplitPlan PlanSplits(const std::vector<SplitPart>& parts, const std::vector<SplitFrame>& frames) {
  SplitPlan plan;
  std::map<std::string, int64_t> filled;
  for (const SplitFrame& f : frames) {
    const std::string& split = AssignSplit(parts, f.group);
    plan.split_of_frame[f.index] = split;
    ++filled[split];
  }
  std::vector<const SplitPart*> wanted;
  for (const SplitPart& part : parts) {
    if (part.fraction > 0) wanted.push_back(&part);
  }
  const bool all_filled = std::all_of(
      wanted.begin(), wanted.end(), [&](const SplitPart* p) { return filled[p->name] > 0; });
  if (all_filled || frames.empty()) return plan;

  const int64_t n = static_cast<int64_t>(frames.size());
  const int64_t k = static_cast<int64_t>(wanted.size());
  if (n < k) {
    throw Error("cannot fill split '" + wanted[n]->name + "': " + std::to_string(n) +
                    " frame(s) for " + std::to_string(k) + " splits with a non-zero fraction",
                Location("--split"));
  }
  // Block sizes: rounded cumulative fractions, then each at least one frame
  // (taken from the largest block).
  std::vector<int64_t> size(k);
  double cumulative = 0, total = 0;
  for (const SplitPart* p : wanted) total += p->fraction;
  int64_t start = 0;
  for (int64_t i = 0; i < k; ++i) {
    cumulative += wanted[i]->fraction / total;
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
  int64_t at = 0;
  for (int64_t i = 0; i < k; ++i) {
    for (int64_t j = 0; j < size[i]; ++j)
      plan.split_of_frame[ordered[at++].index] = wanted[i]->name;
  }
  plan.blocks = true;
  return plan;
}

}  // namespace lsds::convert
