// Flags every lsds command spells the same way (docs/cli.md): --frames (one
// grammar, libs/util/frame_selection.h), --threads, and the frame-range checks
// against a collection or a plan.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <tbb/global_control.h>
#include <CLI/CLI.hpp>

#include "generator/plan/plan.h"
#include "libs/geometry/camera.h"
#include "libs/util/frame_selection.h"

namespace lsds {

// --frames with the shared help text.
CLI::Option* AddFramesOption(CLI::App& app, std::string* text);

// --threads T (0: all cores). With `jobs_alias`, also the hidden, deprecated
// --jobs of older releases.
void AddThreadsOption(CLI::App& app, int* threads, bool jobs_alias = false);

// Warns once on stderr when the deprecated --jobs was used.
void WarnIfJobsUsed(const CLI::App& app);

// --shard I/N: the frames whose index % N == I (parse with ParseShard).
CLI::Option* AddShardOption(CLI::App& app, std::string* text, const std::string& description);

// Parses --shard I/N: exit 2 unless 0 <= I < N.
void ParseShard(const std::string& text, int* index, int* count);

// Parses --depth planar|perspective: exit 2 naming the flag otherwise.
DepthKind ParseDepthFlag(const std::string& text);

// Caps TBB's worker threads for its lifetime (0: no cap).
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();

 private:
  std::unique_ptr<tbb::global_control> control_;
};

// The frame indices of the collection at `root`, in file order.
std::vector<int64_t> CollectionFrameIndices(const std::filesystem::path& root);

// Parses --frames and checks it against the collection's frames: exit 2 naming
// the valid range when it reaches outside them.
FrameSelection SelectCollectionFrames(const std::string& text, const std::filesystem::path& root);

// Checks --frames against the frames of a full plan.
void CheckPlanFrames(const FrameSelection& selection, const Plan& plan);

// The plan of SCENE [CAPTURE] for `seed`, restricted to `selection` when set.
// An out-of-range selection is an error naming the plan's frames (the full
// plan is only made to say so).
Plan PlanSelectedFrames(const std::string& scene,
                        const std::string& capture,
                        uint64_t seed,
                        const std::optional<FrameSelection>& selection);

}  // namespace lsds
