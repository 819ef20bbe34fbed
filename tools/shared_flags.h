// The flags every lsds command takes, spelled and parsed the same way
// (docs/cli.md, "Flags shared by every command"): --frames (one grammar,
// libs/util/frame_selection.h), --threads, -q, --force and --memory-budget, and
// the few other flags several commands share (--shard, --depth).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "libs/collection/frame_selection_check.h"  // SelectCollectionFrames
#include "libs/geometry/camera.h"
#include "libs/util/frame_selection.h"

namespace lsds {

// A common flag a command has no use for (e.g. --frames for `lsds merge`,
// which joins whole shards): listed in its help like every command's, refused
// when given with exit 2, naming the flag and `reason`.
struct UnusedFlag {
  std::string flag;  // "--frames", "--threads", "-q", "--force"
  std::string reason;
};

// The values of the common flags. RunCommand (tools/command.h) applies
// --threads (a cap on TBB's workers), -q (no progress line) and
// --memory-budget for the whole command, and refuses the unused ones; the
// command reads `frames`, `quiet` (its own summary lines) and `force`.
struct CommonFlags {
  std::string frames;  // --frames as given; empty: every frame
  int threads = 0;     // 0: every core
  bool quiet = false;
  bool force = false;
  std::string memory_budget;  // empty: LSDS_MEMORY_BUDGET or 8G
  std::vector<UnusedFlag> unused;
};

// Adds the common flags to `app`, bound to `flags`. `force_help` says what
// --force replaces in this command.
void AddCommonFlags(CLI::App& app,
                    CommonFlags* flags,
                    const std::string& force_help,
                    std::vector<UnusedFlag> unused = {});

// The hidden, deprecated --jobs of older releases, an alias of --threads.
void AddJobsAlias(CLI::App& app, CommonFlags* flags);

// Warns once on stderr when the deprecated --jobs was used.
void WarnIfJobsUsed(const CLI::App& app);

// Throws lsds::Error (exit 2) naming the first unused flag that was given.
void RefuseUnusedFlags(const CLI::App& app, const CommonFlags& flags);

// --shard I/N: the frames whose index % N == I (parse with ParseShard).
CLI::Option* AddShardOption(CLI::App& app, std::string* text, const std::string& description);

// Parses --shard I/N: exit 2 unless 0 <= I < N.
void ParseShard(const std::string& text, int* index, int* count);

// Parses --depth planar|perspective: exit 2 naming the flag otherwise.
DepthKind ParseDepthFlag(const std::string& text);

// The parsed --frames (every frame when not given; its text is then empty).
FrameSelection FramesFlag(const CommonFlags& flags);

}  // namespace lsds
