#include "tools/shared_flags.h"

#include "libs/util/strings.h"

#include <iostream>

#include <tbb/global_control.h>

#include "generator/estimate.h"
#include "generator/lang/planner.h"
#include "libs/collection/collection_reader.h"
#include "libs/util/error.h"

namespace lsds {

CLI::Option* AddFramesOption(CLI::App& app, std::string* text) {
  return app.add_option("--frames",
                        *text,
                        "frame indices: A:B (A to B-1), A: (A to the last), :B (the first to "
                        "B-1) or N (frame N alone)");
}

CLI::Option* AddShardOption(CLI::App& app, std::string* text, const std::string& description) {
  return app.add_option("--shard", *text, description);
}

void ParseShard(const std::string& text, int* index, int* count) {
  const std::vector<std::string> parts = Split(text, '/');
  size_t used_i = 0, used_n = 0;
  try {
    if (parts.size() != 2) throw std::invalid_argument("shard");
    *index = std::stoi(parts[0], &used_i);
    *count = std::stoi(parts[1], &used_n);
  } catch (const std::exception&) {
    throw Error("--shard " + text + ": expected I/N, e.g. 0/4");
  }
  if (used_i != parts[0].size() || used_n != parts[1].size() || *count < 1 || *index < 0 ||
      *index >= *count) {
    throw Error("--shard " + text + ": expected I/N with 0 <= I < N, e.g. 0/4");
  }
}

DepthKind ParseDepthFlag(const std::string& text) {
  DepthKind kind = DepthKind::kPlanar;
  if (!ParseDepthKind(text, &kind))
    throw Error("--depth " + text + ": expected planar or perspective");
  return kind;
}

void AddThreadsOption(CLI::App& app, int* threads, bool jobs_alias) {
  app.add_option("--threads", *threads, "worker threads (0: all cores)")
      ->check(CLI::NonNegativeNumber);
  if (jobs_alias) {
    // Hidden (empty group): kept so that older scripts still run.
    app.add_option("--jobs", *threads, "deprecated: use --threads")
        ->check(CLI::NonNegativeNumber)
        ->group("");
  }
}

void WarnIfJobsUsed(const CLI::App& app) {
  const CLI::Option* jobs = app.get_option_no_throw("--jobs");
  if (jobs != nullptr && jobs->count() > 0) {
    std::cerr << app.get_name() << ": warning: --jobs is deprecated; use --threads\n";
  }
}

ThreadLimit::ThreadLimit(int threads) {
  if (threads > 0) {
    control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                     static_cast<size_t>(threads));
  }
}

ThreadLimit::~ThreadLimit() = default;

std::vector<int64_t> CollectionFrameIndices(const std::filesystem::path& root) {
  const CollectionReader reader(root);
  std::vector<int64_t> indices;
  indices.reserve(reader.frames_in_file());
  reader.ForEachFrameJson([&](const nlohmann::json& frame, const std::string&) {
    const auto it = frame.find("index");
    if (it != frame.end() && it->is_number_integer()) indices.push_back(it->get<int64_t>());
  });
  // Indices are unique and increasing (docs/format.md); sorting keeps the
  // check meaningful on a collection that breaks that rule (validate names it).
  std::sort(indices.begin(), indices.end());
  return indices;
}

FrameSelection SelectCollectionFrames(const std::string& text, const std::filesystem::path& root) {
  FrameSelection selection = ParseFrameSelection(text);
  CheckFrameSelection(selection, CollectionFrameIndices(root), "the collection " + root.string());
  return selection;
}

void CheckPlanFrames(const FrameSelection& selection, const Plan& plan) {
  std::vector<int64_t> indices;
  indices.reserve(plan.frames.size());
  for (const PlannedFrame& frame : plan.frames) indices.push_back(frame.index);
  std::sort(indices.begin(), indices.end());
  CheckFrameSelection(selection, indices, "the plan");
}

Plan PlanSelectedFrames(const std::string& scene,
                        const std::string& capture,
                        uint64_t seed,
                        const std::optional<FrameSelection>& selection) {
  std::optional<std::filesystem::path> capture_path;
  if (!capture.empty()) capture_path = capture;
  FrameRange range;
  if (selection) {
    range.begin = selection->begin;
    range.end = selection->bounded() ? selection->end : -1;
  }
  Plan plan = MakePlan(scene, capture_path, seed, range, gen::MakeFrameEstimatorFactory());
  if (!selection) return plan;
  // Frames are planned independently, so the restricted plan holds exactly the
  // selected frames that exist; anything less means the selection reaches past
  // the plan.
  const bool complete = selection->bounded() ? static_cast<int64_t>(plan.frames.size()) ==
                                                   selection->end - selection->begin
                                             : !plan.frames.empty();
  if (!complete)
    CheckPlanFrames(*selection,
                    MakePlan(scene, capture_path, seed, {}, gen::MakeFrameEstimatorFactory()));
  return plan;
}

}  // namespace lsds
