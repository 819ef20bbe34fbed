// `lsds bundles`: streams the frames of a collection through AnalyzeFrame (TBB,
// a few frames at a time), merges the figures, writes the statistics JSON and,
// on request, derived layers.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "bundles/bundle_stats.h"
#include "libs/collection/model.h"
#include "libs/util/frame_selection.h"

namespace lsds::bundle {

struct RunOptions {
  StatsOptions stats;
  std::filesystem::path output;           // statistics JSON; empty: none
  std::vector<std::string> write_layers;  // DerivedLayerNames()
  FrameRange frames;   // the frame indices analysed (--frames); the others keep their layers
  bool force = false;  // replace the output and earlier derived layers
  std::filesystem::path mixed_map;  // PNG of the first analysed frame; empty: none
  size_t batch = 0;                 // frames decoded at once; 0: the TBB concurrency
};

struct RunResult {
  BundleStats total;
  int64_t frames_analyzed = 0;
  std::string bundle_layer;
};

// The bundle layer of `header`, or lsds::Error telling how to produce one
// (`lsds generate --spp`).
const LayerInfo& FindBundleLayer(const CollectionHeader& header,
                                 const std::string& collection_file);

RunResult RunBundles(const std::filesystem::path& root, const RunOptions& options);

}  // namespace lsds::bundle
