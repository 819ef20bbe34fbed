#include "bundles/stats_json.h"

#include <cmath>
#include <set>

namespace lsds::bundle {

using nlohmann::json;

namespace {

double Ratio(double num, double den) { return den > 0 ? num / den : 0.0; }

json Counter(const MixCounter& c) {
  return {{"pixels", c.pixels},
          {"mixed_pixels", c.mixed},
          {"mixed_fraction", Ratio(static_cast<double>(c.mixed), static_cast<double>(c.pixels))}};
}

json Histogram(const std::vector<double>& upper_edges, const std::vector<uint64_t>& counts) {
  // Bins [edge_{i-1}, edge_i), the first from 0, the last open (null upper
  // edge).
  json bins = json::array();
  for (size_t i = 0; i < counts.size(); ++i) {
    bins.push_back({{"min", i == 0 ? 0.0 : upper_edges[i - 1]},
                    {"max", i < upper_edges.size() ? json(upper_edges[i]) : json(nullptr)},
                    {"pixels", counts[i]}});
  }
  return bins;
}

std::string ClassName(const CollectionHeader& header, uint32_t id) {
  if (id == 0) return "background";
  const ClassInfo* info = header.FindClass(id);
  return info != nullptr ? info->name : "";
}

}  // namespace

json OptionsToJson(const StatsOptions& options) {
  return {{"flying_threshold",
           {{"absolute", options.flying_absolute}, {"relative", options.flying_relative}}},
          {"distance_bands", options.distance_bands},
          {"object_size_bins", options.size_bins},
          {"purity_bins", options.purity_bins}};
}

json StatsToJson(const BundleStats& s,
                 const StatsOptions& options,
                 const CollectionHeader& header) {
  json j;
  const double pixels = static_cast<double>(s.pixels);
  j["frames"] = s.frames;
  j["pixels"] = s.pixels;
  j["empty_pixels"] = s.empty_pixels;
  j["samples"] = s.samples;
  j["samples_per_pixel"] = Ratio(static_cast<double>(s.samples), pixels);
  j["mixed_pixels"] = s.mixed_pixels;
  j["mixed_fraction"] = Ratio(static_cast<double>(s.mixed_pixels), pixels);
  j["class_mixed_pixels"] = s.class_mixed_pixels;
  j["class_mixed_fraction"] = Ratio(static_cast<double>(s.class_mixed_pixels), pixels);

  json per_class = json::array();
  for (const auto& [id, c] : s.per_class) {
    json entry = Counter(c);
    entry["class_id"] = id;
    entry["name"] = ClassName(header, id);
    per_class.push_back(entry);
  }
  j["per_class"] = per_class;

  json bands = json::array();
  for (size_t i = 0; i < s.by_distance.size(); ++i) {
    json entry = Counter(s.by_distance[i]);
    entry["min"] = options.distance_bands[i];
    entry["max"] =
        i + 1 < options.distance_bands.size() ? json(options.distance_bands[i + 1]) : json(nullptr);
    bands.push_back(entry);
  }
  j["by_distance"] = {{"bands", bands}, {"sky_only", Counter(s.sky_only)}};

  std::set<uint32_t> class_ids;
  for (const auto& [key, n] : s.class_mixing) {
    class_ids.insert(key.first);
    class_ids.insert(key.second);
  }
  const std::vector<uint32_t> ordered(class_ids.begin(), class_ids.end());
  json matrix = json::array();
  for (uint32_t a : ordered) {
    json row = json::array();
    for (uint32_t b : ordered) {
      const auto it = s.class_mixing.find({a, b});
      row.push_back(it == s.class_mixing.end() ? 0 : it->second);
    }
    matrix.push_back(row);
  }
  j["class_mixing"] = {{"classes", ordered}, {"samples", matrix}};

  std::vector<double> purity_edges;
  const int bins = static_cast<int>(s.purity_histogram.size());
  for (int i = 1; i < bins; ++i) purity_edges.push_back(static_cast<double>(i) / bins);
  json purity_hist = Histogram(purity_edges, s.purity_histogram);
  if (!purity_hist.empty()) purity_hist.back()["max"] = 1.0;  // purity 1 is in the last bin
  j["purity"] = {{"mean", Ratio(s.purity_sum, pixels)}, {"histogram", purity_hist}};
  j["entropy"] = {
      {"mean_bits", Ratio(s.entropy_sum, pixels)},
      {"mean_bits_mixed", Ratio(s.entropy_sum_mixed, static_cast<double>(s.mixed_pixels))}};

  j["depth"] = {{"pixels", s.depth_pixels},
                {"spread_mean", Ratio(s.depth_spread_sum, static_cast<double>(s.depth_pixels))},
                {"spread_mean_mixed",
                 Ratio(s.depth_spread_sum_mixed, static_cast<double>(s.depth_pixels_mixed))},
                {"spread_max", s.depth_spread_max},
                {"spread_histogram", Histogram(DepthSpreadEdges(), s.depth_spread_histogram)},
                {"flying_pixels", s.flying_pixels},
                {"flying_rate", Ratio(static_cast<double>(s.flying_pixels), pixels)},
                {"flying_rate_of_depth_pixels",
                 Ratio(static_cast<double>(s.flying_pixels), static_cast<double>(s.depth_pixels))}};

  j["normals"] = {
      {"pixels", s.normal_pixels},
      {"spread_mean_deg", Ratio(s.normal_spread_sum, static_cast<double>(s.normal_pixels))},
      {"spread_mean_mixed_deg",
       Ratio(s.normal_spread_sum_mixed, static_cast<double>(s.normal_pixels_mixed))},
      {"spread_max_deg", s.normal_spread_max},
      {"spread_histogram", Histogram(NormalSpreadEdges(), s.normal_spread_histogram)}};

  json sizes = json::array();
  for (size_t i = 0; i < s.by_object_size.size(); ++i) {
    const SizeBin& b = s.by_object_size[i];
    sizes.push_back(
        {{"min_pixels", options.size_bins[i]},
         {"max_pixels",
          i + 1 < options.size_bins.size() ? json(options.size_bins[i + 1]) : json(nullptr)},
         {"objects", b.objects},
         {"pixels", b.pixels},
         {"mixed_pixels", b.mixed},
         {"mixed_fraction", Ratio(static_cast<double>(b.mixed), static_cast<double>(b.pixels))},
         {"mean_object_mixed_share", Ratio(b.share_sum, static_cast<double>(b.objects))}});
  }
  j["by_object_size"] = sizes;
  return j;
}

json ObjectsToJson(const BundleStats& s) {
  json objects = json::array();
  for (const auto& [id, o] : s.objects) {
    objects.push_back(
        {{"instance_id", id},
         {"class_id", o.class_id},
         {"frames", o.frames},
         {"pixels", o.pixels},
         {"mixed_pixels", o.mixed},
         {"mixed_share", Ratio(static_cast<double>(o.mixed), static_cast<double>(o.pixels))}});
  }
  return objects;
}

}  // namespace lsds::bundle
