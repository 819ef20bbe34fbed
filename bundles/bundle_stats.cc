#include "bundles/bundle_stats.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "libs/util/error.h"

namespace lsds::bundle {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

size_t BinOf(const std::vector<double>& upper_edges, double value) {
  // Upper edges; the last bin (index upper_edges.size()) is open.
  return std::upper_bound(upper_edges.begin(), upper_edges.end(), value) - upper_edges.begin();
}

// Per-class counters indexed densely for the usual small ids; large ids fall
// back to a map.
template <typename T>
class IdTable {
 public:
  T& operator[](uint32_t id) {
    if (id < kDense) {
      if (id >= dense_.size()) dense_.resize(id + 1);
      used_.resize(dense_.size(), 0);
      used_[id] = 1;
      return dense_[id];
    }
    return sparse_[id];
  }
  template <typename Fn>
  void ForEach(Fn fn) const {
    for (size_t i = 0; i < dense_.size(); ++i) {
      if (used_[i]) fn(static_cast<uint32_t>(i), dense_[i]);
    }
    for (const auto& [id, value] : sparse_) fn(id, value);
  }

 private:
  static constexpr uint32_t kDense = 1 << 16;
  std::vector<T> dense_;
  std::vector<uint8_t> used_;
  std::map<uint32_t, T> sparse_;
};

struct FrameObject {
  uint32_t class_id = 0;
  uint64_t pixels = 0;
  uint64_t mixed = 0;
};

}  // namespace

const std::vector<double>& DepthSpreadEdges() {
  static const std::vector<double> edges = {0.001, 0.01, 0.1, 1, 10, 100};
  return edges;
}

const std::vector<double>& NormalSpreadEdges() {
  static const std::vector<double> edges = {1, 5, 10, 30, 60, 90};
  return edges;
}

const std::vector<std::string>& BundleChannels() {
  static const std::vector<std::string> channels = {"instanceid", "classid", "Z", "NX", "NY", "NZ"};
  return channels;
}

BundleStats::BundleStats(const StatsOptions& options)
    : by_distance(options.distance_bands.size()),
      purity_histogram(std::max(1, options.purity_bins), 0),
      depth_spread_histogram(DepthSpreadEdges().size() + 1, 0),
      normal_spread_histogram(NormalSpreadEdges().size() + 1, 0),
      by_object_size(options.size_bins.size()) {}

void BundleStats::Merge(const BundleStats& o) {
  auto add_counter = [](MixCounter& a, const MixCounter& b) {
    a.pixels += b.pixels;
    a.mixed += b.mixed;
  };
  frames += o.frames;
  pixels += o.pixels;
  empty_pixels += o.empty_pixels;
  samples += o.samples;
  mixed_pixels += o.mixed_pixels;
  class_mixed_pixels += o.class_mixed_pixels;
  for (const auto& [id, c] : o.per_class) add_counter(per_class[id], c);
  if (by_distance.size() < o.by_distance.size()) by_distance.resize(o.by_distance.size());
  for (size_t i = 0; i < o.by_distance.size(); ++i) add_counter(by_distance[i], o.by_distance[i]);
  add_counter(sky_only, o.sky_only);
  for (const auto& [key, n] : o.class_mixing) class_mixing[key] += n;
  if (purity_histogram.size() < o.purity_histogram.size()) {
    purity_histogram.resize(o.purity_histogram.size());
  }
  for (size_t i = 0; i < o.purity_histogram.size(); ++i)
    purity_histogram[i] += o.purity_histogram[i];
  purity_sum += o.purity_sum;
  entropy_sum += o.entropy_sum;
  entropy_sum_mixed += o.entropy_sum_mixed;
  depth_pixels += o.depth_pixels;
  depth_pixels_mixed += o.depth_pixels_mixed;
  depth_spread_sum += o.depth_spread_sum;
  depth_spread_sum_mixed += o.depth_spread_sum_mixed;
  depth_spread_max = std::max(depth_spread_max, o.depth_spread_max);
  for (size_t i = 0; i < o.depth_spread_histogram.size(); ++i) {
    depth_spread_histogram[i] += o.depth_spread_histogram[i];
  }
  flying_pixels += o.flying_pixels;
  normal_pixels += o.normal_pixels;
  normal_pixels_mixed += o.normal_pixels_mixed;
  normal_spread_sum += o.normal_spread_sum;
  normal_spread_sum_mixed += o.normal_spread_sum_mixed;
  normal_spread_max = std::max(normal_spread_max, o.normal_spread_max);
  for (size_t i = 0; i < o.normal_spread_histogram.size(); ++i) {
    normal_spread_histogram[i] += o.normal_spread_histogram[i];
  }
  for (const auto& [id, c] : o.objects) {
    ObjectCounter& mine = objects[id];
    mine.class_id = c.class_id;
    mine.frames += c.frames;
    mine.pixels += c.pixels;
    mine.mixed += c.mixed;
  }
  if (by_object_size.size() < o.by_object_size.size())
    by_object_size.resize(o.by_object_size.size());
  for (size_t i = 0; i < o.by_object_size.size(); ++i) {
    by_object_size[i].objects += o.by_object_size[i].objects;
    by_object_size[i].pixels += o.by_object_size[i].pixels;
    by_object_size[i].mixed += o.by_object_size[i].mixed;
    by_object_size[i].share_sum += o.by_object_size[i].share_sum;
  }
}

BundleStats AnalyzeFrame(const exr::DeepImage& bundle,
                         const StatsOptions& options,
                         PixelMaps* maps) {
  auto uint_channel = [&](const char* name) {
    const exr::DeepChannel* c = bundle.Find(name);
    if (c == nullptr || c->type != exr::PixelType::kUint) {
      throw Error(std::string("bundle layer needs a UINT channel '") + name + "'");
    }
    return c->uints.data();
  };
  auto float_channel = [&](const char* name, bool required) -> const float* {
    const exr::DeepChannel* c = bundle.Find(name);
    if (c == nullptr || c->type == exr::PixelType::kUint) {
      if (required) throw Error(std::string("bundle layer needs a FLOAT channel '") + name + "'");
      return nullptr;
    }
    return c->floats.data();
  };
  const uint32_t* inst = uint_channel("instanceid");
  const uint32_t* cls = uint_channel("classid");
  const float* zs = float_channel("Z", true);
  const float* nxs = float_channel("NX", false);
  const float* nys = float_channel("NY", false);
  const float* nzs = float_channel("NZ", false);
  const bool has_normals = nxs != nullptr && nys != nullptr && nzs != nullptr;

  BundleStats stats(options);
  stats.frames = 1;
  const size_t pixel_count = bundle.pixel_count();
  // Upper edges of the distance bands and of the purity bins.
  const std::vector<double> band_upper(options.distance_bands.begin() + 1,
                                       options.distance_bands.end());
  const int purity_bins = static_cast<int>(stats.purity_histogram.size());

  if (maps != nullptr) {
    maps->majority_instance.assign(pixel_count, 0);
    maps->majority_class.assign(pixel_count, 0);
    maps->purity.assign(pixel_count, 0.0f);
    maps->mixed.assign(pixel_count, 0);
    maps->edge.assign(pixel_count, 0);
    maps->coverage_counts.assign(pixel_count, 0);
    maps->coverage_instance.clear();
    maps->coverage_class.clear();
    maps->coverage.clear();
  }

  uint32_t max_samples = 0;
  for (uint32_t n : bundle.sample_counts()) max_samples = std::max(max_samples, n);
  std::vector<uint32_t> ids(max_samples), id_counts(max_samples), id_class(max_samples);
  std::vector<uint32_t> classes(max_samples), class_counts(max_samples);
  std::vector<uint32_t> order(max_samples);

  IdTable<MixCounter> per_class;
  IdTable<uint64_t> pure_class_samples;
  std::unordered_map<uint64_t, uint64_t> class_pairs;
  std::unordered_map<uint32_t, FrameObject> objects;
  uint32_t last_object_id = 0;
  FrameObject* last_object = nullptr;

  const std::vector<uint64_t>& offsets = bundle.offsets();
  const std::vector<uint32_t>& counts = bundle.sample_counts();
  for (size_t p = 0; p < pixel_count; ++p) {
    const uint32_t n = counts[p];
    if (n == 0) {
      ++stats.empty_pixels;
      continue;
    }
    const uint64_t first = offsets[p];
    ++stats.pixels;
    stats.samples += n;

    // Distinct instance and class ids with their sample counts, in order of
    // first appearance.
    uint32_t k = 0, kc = 0;
    for (uint32_t s = 0; s < n; ++s) {
      const uint32_t id = inst[first + s];
      uint32_t j = 0;
      while (j < k && ids[j] != id) ++j;
      if (j == k) {
        ids[k] = id;
        id_counts[k] = 0;
        id_class[k] = cls[first + s];
        ++k;
      }
      ++id_counts[j];
      const uint32_t c = cls[first + s];
      j = 0;
      while (j < kc && classes[j] != c) ++j;
      if (j == kc) {
        classes[kc] = c;
        class_counts[kc] = 0;
        ++kc;
      }
      ++class_counts[j];
    }
    const bool mixed = k > 1;
    stats.mixed_pixels += mixed;
    stats.class_mixed_pixels += kc > 1;

    // Majority id: the most samples; ties go to the id seen first (sample 0 is
    // nearest the centre).
    uint32_t best = 0;
    for (uint32_t j = 1; j < k; ++j) {
      if (id_counts[j] > id_counts[best]) best = j;
    }
    const double inv_n = 1.0 / n;
    const double purity = id_counts[best] * inv_n;
    stats.purity_sum += purity;
    stats.purity_histogram[std::min(purity_bins - 1, static_cast<int>(purity * purity_bins))]++;
    if (mixed) {
      double entropy = 0;
      for (uint32_t j = 0; j < k; ++j) {
        const double q = id_counts[j] * inv_n;
        entropy -= q * std::log2(q);
      }
      stats.entropy_sum += entropy;
      stats.entropy_sum_mixed += entropy;
    }

    for (uint32_t j = 0; j < kc; ++j) {
      MixCounter& c = per_class[classes[j]];
      ++c.pixels;
      c.mixed += mixed;
    }
    if (kc == 1) {
      pure_class_samples[classes[0]] += n;
    } else {
      for (uint32_t a = 0; a < kc; ++a) {
        for (uint32_t b = 0; b < kc; ++b) {
          if (a != b) class_pairs[(uint64_t{classes[a]} << 32) | classes[b]] += class_counts[a];
        }
      }
    }
    for (uint32_t j = 0; j < k; ++j) {
      if (ids[j] == 0) continue;
      if (last_object == nullptr || last_object_id != ids[j]) {
        last_object_id = ids[j];
        last_object = &objects[ids[j]];
        last_object->class_id = id_class[j];
      }
      ++last_object->pixels;
      last_object->mixed += mixed;
    }

    // Depth: spread of the finite depths, and whether their average would lie
    // in empty space.
    uint32_t m = 0;
    double zmin = INFINITY, zmax = -INFINITY, zsum = 0;
    for (uint32_t s = 0; s < n; ++s) {
      const float z = zs[first + s];
      if (!std::isfinite(z)) continue;
      ++m;
      zmin = std::min<double>(zmin, z);
      zmax = std::max<double>(zmax, z);
      zsum += z;
    }
    bool depth_edge = false;
    if (m == 0) {
      ++stats.sky_only.pixels;
      stats.sky_only.mixed += mixed;
    } else {
      MixCounter& band = stats.by_distance[BinOf(band_upper, zmin)];
      ++band.pixels;
      band.mixed += mixed;
    }
    if (m >= 2) {
      const double spread = zmax - zmin;
      ++stats.depth_pixels;
      stats.depth_spread_sum += spread;
      if (mixed) {
        ++stats.depth_pixels_mixed;
        stats.depth_spread_sum_mixed += spread;
      }
      stats.depth_spread_max = std::max(stats.depth_spread_max, spread);
      stats.depth_spread_histogram[BinOf(DepthSpreadEdges(), spread)]++;
      const double average = zsum / m;
      const double threshold =
          std::max(options.flying_absolute, options.flying_relative * std::abs(average));
      double nearest = INFINITY;
      for (uint32_t s = 0; s < n; ++s) {
        const float z = zs[first + s];
        if (std::isfinite(z)) nearest = std::min(nearest, std::abs(average - z));
      }
      stats.flying_pixels += nearest > threshold;
      depth_edge = spread > threshold;
    }

    // Normals: the largest angle between a sample normal and the pixel's mean
    // normal.
    if (has_normals) {
      uint32_t q = 0;
      double sx = 0, sy = 0, sz = 0;
      for (uint32_t s = 0; s < n; ++s) {
        const double x = nxs[first + s], y = nys[first + s], z = nzs[first + s];
        const double len2 = x * x + y * y + z * z;
        if (!(len2 > 0) || !std::isfinite(len2)) continue;
        const double inv = 1.0 / std::sqrt(len2);
        sx += x * inv;
        sy += y * inv;
        sz += z * inv;
        ++q;
      }
      if (q >= 2) {
        const double len = std::sqrt(sx * sx + sy * sy + sz * sz);
        double min_dot = -1;
        if (len > 1e-12) {
          min_dot = 1;
          for (uint32_t s = 0; s < n; ++s) {
            const double x = nxs[first + s], y = nys[first + s], z = nzs[first + s];
            const double len2 = x * x + y * y + z * z;
            if (!(len2 > 0) || !std::isfinite(len2)) continue;
            min_dot = std::min(min_dot, (x * sx + y * sy + z * sz) / (std::sqrt(len2) * len));
          }
        }
        const double angle = std::acos(std::clamp(min_dot, -1.0, 1.0)) * kRadToDeg;
        ++stats.normal_pixels;
        stats.normal_spread_sum += angle;
        if (mixed) {
          ++stats.normal_pixels_mixed;
          stats.normal_spread_sum_mixed += angle;
        }
        stats.normal_spread_max = std::max(stats.normal_spread_max, angle);
        stats.normal_spread_histogram[BinOf(NormalSpreadEdges(), angle)]++;
      }
    }

    if (maps != nullptr) {
      maps->majority_instance[p] = ids[best];
      maps->majority_class[p] = id_class[best];
      maps->purity[p] = static_cast<float>(purity);
      maps->mixed[p] = mixed;
      maps->edge[p] = mixed || depth_edge;
      maps->coverage_counts[p] = k;
      for (uint32_t j = 0; j < k; ++j) order[j] = j;
      std::stable_sort(order.begin(), order.begin() + k, [&](uint32_t a, uint32_t b) {
        return id_counts[a] > id_counts[b];
      });
      for (uint32_t j = 0; j < k; ++j) {
        maps->coverage_instance.push_back(ids[order[j]]);
        maps->coverage_class.push_back(id_class[order[j]]);
        maps->coverage.push_back(static_cast<float>(id_counts[order[j]] * inv_n));
      }
    }
  }

  per_class.ForEach([&](uint32_t id, const MixCounter& c) { stats.per_class[id] = c; });
  pure_class_samples.ForEach([&](uint32_t id, uint64_t n) { stats.class_mixing[{id, id}] += n; });
  for (const auto& [key, n] : class_pairs) {
    stats.class_mixing[{static_cast<uint32_t>(key >> 32), static_cast<uint32_t>(key)}] += n;
  }
  for (const auto& [id, o] : objects) {
    ObjectCounter& c = stats.objects[id];
    c.class_id = o.class_id;
    c.frames = 1;
    c.pixels = o.pixels;
    c.mixed = o.mixed;
    const auto& edges = options.size_bins;
    const size_t bin =
        std::upper_bound(edges.begin(), edges.end(), static_cast<int64_t>(o.pixels)) -
        edges.begin();
    if (bin == 0) continue;  // smaller than the first edge
    SizeBin& b = stats.by_object_size[bin - 1];
    ++b.objects;
    b.pixels += o.pixels;
    b.mixed += o.mixed;
    b.share_sum += static_cast<double>(o.mixed) / o.pixels;
  }
  return stats;
}

}  // namespace lsds::bundle
