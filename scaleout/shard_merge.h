// Joining the shards of one run (`lsds generate --shard I/N`, each a
// collection whose provenance records its shard) into the collection the run
// would have written in one process: the same collection.json, metadata.json
// and layer files, byte for byte (docs/scale-out.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace lsds {

struct MergeOptions {
  std::vector<std::filesystem::path> shards;  // shard collections, any order
  std::filesystem::path output;
  bool force = false;  // replace an existing output
  bool progress = true;
};

struct MergeSummary {
  int shards = 0;
  int64_t frames = 0;
  int64_t files = 0;   // layer files copied
  uint64_t bytes = 0;  // bytes of the layer files copied
  double seconds = 0;
};

// Checks that the shards belong to one run (same header apart from the shard
// index and frame count, same metadata header) and hold every frame of the run
// exactly once, then writes the run's collection under a temporary name
// beside `output` and renames it into place. Frames are streamed: memory holds
// a few frames per shard, never the collection. The shards are only read.
// Throws lsds::Error (exit 2) naming the shard, file and the missing, doubled
// or foreign frames.
MergeSummary MergeShards(const MergeOptions& options);

}  // namespace lsds
