#include "bundles/bundle_stats.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

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

// The bundle's per-sample channels; the normals are optional (all three or none).
struct SampleChannels {
  const uint32_t* inst = nullptr;
  const uint32_t* cls = nullptr;
  const float* zs = nullptr;
  const float* nxs = nullptr;
  const float* nys = nullptr;
  const float* nzs = nullptr;
  bool has_normals = false;
};

SampleChannels ReadSampleChannels(const exr::DeepImage& bundle) {
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
  SampleChannels ch;
  ch.inst = uint_channel("instanceid");
  ch.cls = uint_channel("classid");
  ch.zs = float_channel("Z", true);
  ch.nxs = float_channel("NX", false);
  ch.nys = float_channel("NY", false);
  ch.nzs = float_channel("NZ", false);
  ch.has_normals = ch.nxs != nullptr && ch.nys != nullptr && ch.nzs != nullptr;
  return ch;
}

void ResetMaps(size_t pixel_count, PixelMaps* maps) {
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

// One frame's analysis, one pixel at a time. Each stage of a pixel (ids, purity, classes,
// depth, normals, maps) is a method over the pixel's samples; the scratch buffers are sized
// once for the deepest pixel so the loop allocates nothing.
class FrameAnalyzer {
 public:
  FrameAnalyzer(const exr::DeepImage& bundle, const StatsOptions& options, PixelMaps* maps)
      : bundle_(bundle),
        options_(options),
        maps_(maps),
        ch_(ReadSampleChannels(bundle)),
        stats_(options),
        // Upper edges of the distance bands and of the purity bins.
        band_upper_(options.distance_bands.begin() + 1, options.distance_bands.end()),
        purity_bins_(static_cast<int>(stats_.purity_histogram.size())) {
    stats_.frames = 1;
    if (maps_ != nullptr) ResetMaps(bundle.pixel_count(), maps_);
    uint32_t max_samples = 0;
    for (uint32_t n : bundle.sample_counts()) max_samples = std::max(max_samples, n);
    ids_.resize(max_samples);
    id_counts_.resize(max_samples);
    id_class_.resize(max_samples);
    classes_.resize(max_samples);
    class_counts_.resize(max_samples);
    order_.resize(max_samples);
  }

  BundleStats Run() {
    const size_t pixel_count = bundle_.pixel_count();
    const std::vector<uint64_t>& offsets = bundle_.offsets();
    const std::vector<uint32_t>& counts = bundle_.sample_counts();
    for (size_t p = 0; p < pixel_count; ++p) {
      if (counts[p] == 0) {
        ++stats_.empty_pixels;
        continue;
      }
      AnalyzePixel(p, offsets[p], counts[p]);
    }
    Finish();
    return std::move(stats_);
  }

 private:
  void AnalyzePixel(size_t p, uint64_t first, uint32_t n) {
    ++stats_.pixels;
    stats_.samples += n;
    CountIds(first, n);
    const bool mixed = k_ > 1;
    stats_.mixed_pixels += mixed;
    stats_.class_mixed_pixels += kc_ > 1;
    const uint32_t best = MajorityId();
    const double inv_n = 1.0 / n;
    const double purity = id_counts_[best] * inv_n;
    AddPurity(purity, inv_n, mixed);
    AddClasses(n, mixed);
    AddObjects(mixed);
    const bool depth_edge = AddDepth(first, n, mixed);
    if (ch_.has_normals) AddNormalSpread(first, n, mixed);
    if (maps_ != nullptr) WriteMaps(p, best, purity, inv_n, mixed, depth_edge);
  }

  // Distinct instance and class ids with their sample counts, in order of
  // first appearance.
  void CountIds(uint64_t first, uint32_t n) {
    k_ = 0;
    kc_ = 0;
    for (uint32_t s = 0; s < n; ++s) {
      const uint32_t id = ch_.inst[first + s];
      uint32_t j = 0;
      while (j < k_ && ids_[j] != id) ++j;
      if (j == k_) {
        ids_[k_] = id;
        id_counts_[k_] = 0;
        id_class_[k_] = ch_.cls[first + s];
        ++k_;
      }
      ++id_counts_[j];
      const uint32_t c = ch_.cls[first + s];
      j = 0;
      while (j < kc_ && classes_[j] != c) ++j;
      if (j == kc_) {
        classes_[kc_] = c;
        class_counts_[kc_] = 0;
        ++kc_;
      }
      ++class_counts_[j];
    }
  }

  // Majority id: the most samples; ties go to the id seen first (sample 0 is
  // nearest the centre).
  uint32_t MajorityId() const {
    uint32_t best = 0;
    for (uint32_t j = 1; j < k_; ++j) {
      if (id_counts_[j] > id_counts_[best]) best = j;
    }
    return best;
  }

  void AddPurity(double purity, double inv_n, bool mixed) {
    stats_.purity_sum += purity;
    stats_.purity_histogram[std::min(purity_bins_ - 1, static_cast<int>(purity * purity_bins_))]++;
    if (mixed) {
      double entropy = 0;
      for (uint32_t j = 0; j < k_; ++j) {
        const double q = id_counts_[j] * inv_n;
        entropy -= q * std::log2(q);
      }
      stats_.entropy_sum += entropy;
      stats_.entropy_sum_mixed += entropy;
    }
  }

  // Per-class mixing, and which classes share a pixel with which (weighted by samples).
  void AddClasses(uint32_t n, bool mixed) {
    for (uint32_t j = 0; j < kc_; ++j) {
      MixCounter& c = per_class_[classes_[j]];
      ++c.pixels;
      c.mixed += mixed;
    }
    if (kc_ == 1) {
      pure_class_samples_[classes_[0]] += n;
      return;
    }
    for (uint32_t a = 0; a < kc_; ++a) {
      for (uint32_t b = 0; b < kc_; ++b) {
        if (a != b) class_pairs_[(uint64_t{classes_[a]} << 32) | classes_[b]] += class_counts_[a];
      }
    }
  }

  // Per-object pixels; the last object is cached because neighbouring pixels mostly share one.
  void AddObjects(bool mixed) {
    for (uint32_t j = 0; j < k_; ++j) {
      if (ids_[j] == 0) continue;
      if (last_object_ == nullptr || last_object_id_ != ids_[j]) {
        last_object_id_ = ids_[j];
        last_object_ = &objects_[ids_[j]];
        last_object_->class_id = id_class_[j];
      }
      ++last_object_->pixels;
      last_object_->mixed += mixed;
    }
  }

  // Depth: spread of the finite depths, and whether their average would lie
  // in empty space. Returns whether the pixel is a depth edge.
  bool AddDepth(uint64_t first, uint32_t n, bool mixed) {
    uint32_t m = 0;
    double zmin = INFINITY, zmax = -INFINITY, zsum = 0;
    for (uint32_t s = 0; s < n; ++s) {
      const float z = ch_.zs[first + s];
      if (!std::isfinite(z)) continue;
      ++m;
      zmin = std::min<double>(zmin, z);
      zmax = std::max<double>(zmax, z);
      zsum += z;
    }
    if (m == 0) {
      ++stats_.sky_only.pixels;
      stats_.sky_only.mixed += mixed;
    } else {
      MixCounter& band = stats_.by_distance[BinOf(band_upper_, zmin)];
      ++band.pixels;
      band.mixed += mixed;
    }
    if (m < 2) return false;
    const double spread = zmax - zmin;
    ++stats_.depth_pixels;
    stats_.depth_spread_sum += spread;
    if (mixed) {
      ++stats_.depth_pixels_mixed;
      stats_.depth_spread_sum_mixed += spread;
    }
    stats_.depth_spread_max = std::max(stats_.depth_spread_max, spread);
    stats_.depth_spread_histogram[BinOf(DepthSpreadEdges(), spread)]++;
    const double average = zsum / m;
    const double threshold =
        std::max(options_.flying_absolute, options_.flying_relative * std::abs(average));
    double nearest = INFINITY;
    for (uint32_t s = 0; s < n; ++s) {
      const float z = ch_.zs[first + s];
      if (std::isfinite(z)) nearest = std::min(nearest, std::abs(average - z));
    }
    stats_.flying_pixels += nearest > threshold;
    return spread > threshold;
  }

  // Normals: the largest angle between a sample normal and the pixel's mean
  // normal.
  void AddNormalSpread(uint64_t first, uint32_t n, bool mixed) {
    uint32_t q = 0;
    double sx = 0, sy = 0, sz = 0;
    for (uint32_t s = 0; s < n; ++s) {
      const double x = ch_.nxs[first + s], y = ch_.nys[first + s], z = ch_.nzs[first + s];
      const double len2 = x * x + y * y + z * z;
      if (!(len2 > 0) || !std::isfinite(len2)) continue;
      const double inv = 1.0 / std::sqrt(len2);
      sx += x * inv;
      sy += y * inv;
      sz += z * inv;
      ++q;
    }
    if (q < 2) return;
    const double len = std::sqrt(sx * sx + sy * sy + sz * sz);
    double min_dot = -1;
    if (len > 1e-12) {
      min_dot = 1;
      for (uint32_t s = 0; s < n; ++s) {
        const double x = ch_.nxs[first + s], y = ch_.nys[first + s], z = ch_.nzs[first + s];
        const double len2 = x * x + y * y + z * z;
        if (!(len2 > 0) || !std::isfinite(len2)) continue;
        min_dot = std::min(min_dot, (x * sx + y * sy + z * sz) / (std::sqrt(len2) * len));
      }
    }
    const double angle = std::acos(std::clamp(min_dot, -1.0, 1.0)) * kRadToDeg;
    ++stats_.normal_pixels;
    stats_.normal_spread_sum += angle;
    if (mixed) {
      ++stats_.normal_pixels_mixed;
      stats_.normal_spread_sum_mixed += angle;
    }
    stats_.normal_spread_max = std::max(stats_.normal_spread_max, angle);
    stats_.normal_spread_histogram[BinOf(NormalSpreadEdges(), angle)]++;
  }

  // The per-pixel maps; coverage lists the ids by falling share (ties keep first appearance).
  void WriteMaps(
      size_t p, uint32_t best, double purity, double inv_n, bool mixed, bool depth_edge) {
    maps_->majority_instance[p] = ids_[best];
    maps_->majority_class[p] = id_class_[best];
    maps_->purity[p] = static_cast<float>(purity);
    maps_->mixed[p] = mixed;
    maps_->edge[p] = mixed || depth_edge;
    maps_->coverage_counts[p] = k_;
    for (uint32_t j = 0; j < k_; ++j) order_[j] = j;
    std::stable_sort(order_.begin(), order_.begin() + k_, [&](uint32_t a, uint32_t b) {
      return id_counts_[a] > id_counts_[b];
    });
    for (uint32_t j = 0; j < k_; ++j) {
      maps_->coverage_instance.push_back(ids_[order_[j]]);
      maps_->coverage_class.push_back(id_class_[order_[j]]);
      maps_->coverage.push_back(static_cast<float>(id_counts_[order_[j]] * inv_n));
    }
  }

  // Moves the frame's tallies into the stats: classes, class mixing, objects and their size bins.
  void Finish() {
    per_class_.ForEach([&](uint32_t id, const MixCounter& c) { stats_.per_class[id] = c; });
    pure_class_samples_.ForEach([&](uint32_t id, uint64_t n) {
      stats_.class_mixing[{id, id}] += n;
    });
    for (const auto& [key, n] : class_pairs_) {
      stats_.class_mixing[{static_cast<uint32_t>(key >> 32), static_cast<uint32_t>(key)}] += n;
    }
    for (const auto& [id, o] : objects_) {
      ObjectCounter& c = stats_.objects[id];
      c.class_id = o.class_id;
      c.frames = 1;
      c.pixels = o.pixels;
      c.mixed = o.mixed;
      const auto& edges = options_.size_bins;
      const size_t bin =
          std::upper_bound(edges.begin(), edges.end(), static_cast<int64_t>(o.pixels)) -
          edges.begin();
      if (bin == 0) continue;  // smaller than the first edge
      SizeBin& b = stats_.by_object_size[bin - 1];
      ++b.objects;
      b.pixels += o.pixels;
      b.mixed += o.mixed;
      b.share_sum += static_cast<double>(o.mixed) / o.pixels;
    }
  }

  const exr::DeepImage& bundle_;
  const StatsOptions& options_;
  PixelMaps* maps_;
  const SampleChannels ch_;
  BundleStats stats_;
  const std::vector<double> band_upper_;
  const int purity_bins_;

  // The current pixel: its k_ distinct ids and kc_ distinct classes.
  std::vector<uint32_t> ids_, id_counts_, id_class_, classes_, class_counts_, order_;
  uint32_t k_ = 0, kc_ = 0;

  IdTable<MixCounter> per_class_;
  IdTable<uint64_t> pure_class_samples_;
  std::unordered_map<uint64_t, uint64_t> class_pairs_;
  std::unordered_map<uint32_t, FrameObject> objects_;
  uint32_t last_object_id_ = 0;
  FrameObject* last_object_ = nullptr;
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
  return FrameAnalyzer(bundle, options, maps).Run();
}

}  // namespace lsds::bundle
