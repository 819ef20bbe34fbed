#include "tools/shared_flags.h"

#include <algorithm>
#include <iostream>

#include "libs/collection/collection_reader.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds {

void AddCommonFlags(CLI::App& app,
                    CommonFlags* flags,
                    const std::string& force_help,
                    std::vector<UnusedFlag> unused) {
  // A flag the command has no use for says so in its help too.
  auto help = [&](const std::string& flag, const std::string& text) {
    for (const UnusedFlag& u : unused)
      if (u.flag == flag) return "not used here: " + u.reason;
    return text;
  };
  app.add_option("--frames",
                 flags->frames,
                 help("--frames",
                      "frame indices: A:B (A to B-1), A: (A to the last), :B (the first to "
                      "B-1) or N (frame N alone)"));
  app.add_option("--threads", flags->threads, help("--threads", "worker threads (0: all cores)"))
      ->check(CLI::NonNegativeNumber);
  app.add_flag("-q,--quiet",
               flags->quiet,
               help("-q", "no progress line and no summary (the command's own output stays)"));
  app.add_flag("--force", flags->force, help("--force", force_help));
  app.add_option("--memory-budget",
                 flags->memory_budget,
                 "memory one image, film or decoded layer may take, e.g. 16G "
                 "(default: LSDS_MEMORY_BUDGET or 8G)");
  flags->unused = std::move(unused);
}

void AddJobsAlias(CLI::App& app, CommonFlags* flags) {
  // Hidden (empty group): kept so that older scripts still run.
  app.add_option("--jobs", flags->threads, "deprecated: use --threads")
      ->check(CLI::NonNegativeNumber)
      ->group("");
}

void WarnIfJobsUsed(const CLI::App& app) {
  const CLI::Option* jobs = app.get_option_no_throw("--jobs");
  if (jobs != nullptr && jobs->count() > 0) {
    std::cerr << app.get_name() << ": warning: --jobs is deprecated; use --threads\n";
  }
}

void RefuseUnusedFlags(const CLI::App& app, const CommonFlags& flags) {
  for (const UnusedFlag& unused : flags.unused) {
    const CLI::Option* option = app.get_option_no_throw(unused.flag);
    if (option == nullptr || option->count() == 0) continue;
    std::string where = unused.flag;
    if (option->get_expected_min() > 0 && !option->results().empty())
      where += " " + option->results().front();
    throw Error(unused.reason, Location(where));
  }
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

FrameSelection FramesFlag(const CommonFlags& flags) {
  return flags.frames.empty() ? FrameSelection{} : ParseFrameSelection(flags.frames);
}

}  // namespace lsds
