// What `lsds info` reports: a one-pass summary of a collection.
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "libs/collection/collection_reader.h"

namespace lsds {

struct LayerSummary {
  int64_t files = 0;
  int64_t missing_files = 0;
  int64_t bytes = 0;
  // The channels the layer's first file stores, from its EXR header (a residual
  // layout stores dX, dY, dZ as UINT where readers get X, Y, Z as FLOAT); empty
  // with `stored_error` set when no file's header could be read.
  std::vector<exr::ChannelSpec> stored_channels;
  std::string stored_error;
};

// The layer's storage layout ("residual", "float", "compact", "full"), or ""
// for layers that have one storage only.
std::string LayerLayoutName(const LayerInfo& layer);

struct ClassSummary {
  int64_t objects = 0;              // object entries over all frames
  std::set<uint32_t> instance_ids;  // distinct instances
};

struct CollectionSummary {
  int64_t frames = 0;
  double time_min = 0, time_max = 0;
  std::map<std::string, int> resolutions;     // "1024x768" -> frames
  std::map<std::string, int64_t> rig_frames;  // rig camera -> frames (rig collections)
  double hfov_min_deg = 0, hfov_max_deg = 0;
  double camera_height_min = 0,
         camera_height_max = 0;  // camera centre "up" coordinate, world units
  std::map<std::string, LayerSummary> layers;
  std::map<uint32_t, ClassSummary> classes;
  int64_t objects = 0;
  int64_t collection_json_bytes = 0;
  int64_t total_bytes = 0;
};

// A collection's folder, header and summary.
struct CollectionInfo {
  std::filesystem::path root;
  CollectionHeader header;
  CollectionSummary summary;
};

// Reads collection.json once (collection_read_once.h), stat-ing each layer
// file and reading the header of its first one, not decoding pixels. A bad
// collection is the lsds::Error CollectionReader reports.
CollectionInfo SummarizeCollection(const std::filesystem::path& root);

nlohmann::json SummaryToJson(const CollectionInfo& info);
std::string SummaryToText(const CollectionInfo& info);

}  // namespace lsds
