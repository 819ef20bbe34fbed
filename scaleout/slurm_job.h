// The scripts of a Slurm run of `lsds generate` (docs/scale-out.md): a job
// array whose task i renders shard i/N with --resume, and a merge job that
// runs only when every task has succeeded (--dependency=afterok) and is
// cancelled when one fails (--kill-on-invalid-dep=yes). Plain text, meant to
// be read and adapted.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace lsds {

struct SlurmJob {
  std::filesystem::path lsds;     // the lsds binary the jobs run (absolute)
  std::filesystem::path scene;    // LSCENE (absolute)
  std::filesystem::path capture;  // LCAP (absolute), may be empty
  std::filesystem::path output;   // the merged collection (absolute)
  std::filesystem::path work;     // shards, logs, scripts (absolute)
  int shards = 2;                 // N, >= 2
  std::optional<uint64_t> seed;
  std::optional<int> spp;
  std::string frames;        // --frames, as given; empty: all
  std::string depth;         // --depth, empty: the default
  bool compact = false;      // --compact: the residual worldposition and motion layouts
  bool force_merge = false;  // the merge replaces an existing output
  // Resources (empty / 0: the cluster's defaults).
  std::string partition;
  std::string time;  // per task, Slurm's format (e.g. 2:00:00)
  int cpus_per_task = 0;
  std::string mem;   // per task, e.g. 8G
  int throttle = 0;  // at most K tasks at once (array %K)
  std::string job_name = "lsds";
  std::string account;

  // Throws lsds::Error for inconsistent settings and values that would break
  // a script line. The values passed on to lsds generate (spp, depth, frames)
  // are generate's to check: `lsds submit` runs GenerateOptions::Check.
  void Check() const;
};

struct SlurmScripts {
  std::string generate;  // generate.sbatch: the job array
  std::string merge;     // merge.sbatch: the merge job
  std::string submit;    // submit.sh: sbatch of both, the merge depending on
                         // the array
};

SlurmScripts MakeSlurmScripts(const SlurmJob& job);

// `text` quoted for a POSIX shell ('...' with ' written '\'').
std::string ShellQuote(const std::string& text);

}  // namespace lsds
