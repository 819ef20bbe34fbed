// lsds merge SHARD_DIR... -o COLLECTION: the shards of one `lsds generate
// --shard I/N` run joined into the run's collection (libs/collection/
// shard_merge.h does the work).
#include <iostream>

#include "libs/collection/collection_guard.h"
#include "libs/util/error.h"
#include "scaleout/shard_merge.h"
#include "tools/command.h"

namespace lsds {

int RunMerge(int argc, char** argv) {
  CLI::App app{
      "Join the shards of one run (lsds generate --shard I/N) into the "
      "collection a single run writes, byte for byte",
      "lsds merge"};
  MergeOptions options;
  std::vector<std::string> shards;
  std::string output;
  app.add_option("SHARD_DIR", shards, "shard collections, any order")->required();
  app.add_option("-o,--output", output, "the merged collection folder")->required();
  CommonFlags common;
  AddCommonFlags(app,
                 &common,
                 "replace an existing output folder",
                 {{"--frames",
                   "lsds merge joins whole shards into the run's collection; select frames "
                   "when generating (lsds generate --frames)"}});
  return RunCommand(app, common, argc, argv, [&]() {
    OutputGuard guard("lsds merge");
    for (const std::string& shard : shards) {
      GuardCollection(&guard, shard, CollectionAccess::kReadOnly);
      options.shards.push_back(shard);
    }
    guard.CheckOutput(output, "-o");
    options.output = output;
    options.force = common.force;
    options.progress = !common.quiet;
    const MergeSummary summary = MergeShards(options);
    if (!common.quiet) {
      std::cerr << "lsds merge: " << summary.shards << " shards, " << summary.frames << " frames, "
                << summary.files << " layer files (" << summary.bytes / 1e6 << " MB) in "
                << summary.seconds << " s -> " << output << "\n";
    }
    return kExitOk;
  });
}

}  // namespace lsds
