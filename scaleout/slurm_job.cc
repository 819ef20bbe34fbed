#include "scaleout/slurm_job.h"

#include <sstream>

#include "libs/util/error.h"
#include "libs/util/text_check.h"

namespace lsds {

namespace {

// Values that land in #SBATCH lines must not break the line or the option: a
// carriage return or another control character reaches sbatch as part of the
// value, and every task is refused on the cluster.
void CheckSbatchValue(const std::string& flag, const std::string& value) {
  for (char c : value) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f || c == ' ' || c == '#' || c == '\'' || c == '"')
      throw Error(flag + " '" + Excerpt(value) +
                  "': control characters, spaces, quotes and '#' are not allowed");
  }
}

std::string Q(const std::filesystem::path& path) { return ShellQuote(path.string()); }

// The #SBATCH resource lines shared by both jobs.
std::string ResourceLines(const SlurmJob& job, bool with_cpus) {
  std::ostringstream s;
  if (!job.partition.empty()) s << "#SBATCH --partition=" << job.partition << "\n";
  if (!job.account.empty()) s << "#SBATCH --account=" << job.account << "\n";
  if (!job.time.empty()) s << "#SBATCH --time=" << job.time << "\n";
  if (with_cpus && job.cpus_per_task > 0)
    s << "#SBATCH --cpus-per-task=" << job.cpus_per_task << "\n";
  if (with_cpus && !job.mem.empty()) s << "#SBATCH --mem=" << job.mem << "\n";
  return s.str();
}

}  // namespace

std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\'')
      quoted += "'\\''";
    else
      quoted += c;
  }
  return quoted + "'";
}

void SlurmJob::Check() const {
  if (shards < 2)
    throw Error("--shards " + std::to_string(shards) +
                ": at least 2 (one shard is a plain lsds generate)");
  if (throttle < 0) throw Error("--throttle must be >= 0 (0: no limit)");
  if (cpus_per_task < 0) throw Error("--cpus-per-task must be >= 0");
  CheckSbatchValue("--partition", partition);
  CheckSbatchValue("--account", account);
  CheckSbatchValue("--time", time);
  CheckSbatchValue("--mem", mem);
  CheckSbatchValue("--job-name", job_name);
  if (job_name.empty()) throw Error("--job-name must not be empty");
  // Slurm expands %A, %a, %j in --output; a % in the folder name
  // would be expanded too.
  if (work.string().find('%') != std::string::npos || work.string().find('\n') != std::string::npos)
    throw Error("the work folder's path must not hold '%' or a newline", Location(work.string()));
}

SlurmScripts MakeSlurmScripts(const SlurmJob& job) {
  job.Check();
  const std::string n = std::to_string(job.shards);
  const std::string last = std::to_string(job.shards - 1);
  SlurmScripts scripts;

  std::ostringstream g;
  g << "#!/bin/bash\n"
    << "# Written by `lsds submit slurm` (lsds " << LSDS_VERSION
    << "); docs/scale-out.md explains it.\n"
    << "# One task of a job array per shard: task i renders the frames whose "
       "index % "
    << n << " == i\n"
    << "# into $WORK/shard-i. Every frame is rendered from the plan and its "
       "seed alone, so the\n"
    << "# shards hold exactly the frames (bytes) one process would write; "
       "merge.sbatch joins them.\n"
    << "#SBATCH --job-name=" << job.job_name << "-generate\n"
    << "#SBATCH --array=0-" << last << (job.throttle > 0 ? "%" + std::to_string(job.throttle) : "")
    << "\n"
    << ResourceLines(job, true) << "set -euo pipefail\n"
    << "LSDS=" << Q(job.lsds) << "\n"
    << "WORK=" << Q(job.work) << "\n"
    << "# --resume: a task that was interrupted, requeued or submitted again "
       "keeps its complete\n"
    << "# frames and renders only the rest; a finished shard is left as it "
       "is.\n"
    << "exec \"$LSDS\" generate " << Q(job.scene);
  if (!job.capture.empty()) g << " " << Q(job.capture);
  if (job.seed) g << " --seed " << *job.seed;
  if (job.spp) g << " --spp " << *job.spp;
  if (!job.frames.empty()) g << " --frames " << ShellQuote(job.frames);
  if (!job.depth.empty()) g << " --depth " << ShellQuote(job.depth);
  if (job.compact) g << " --compact";
  g << " \\\n    --shard \"${SLURM_ARRAY_TASK_ID}/" << n << "\""
    << " --threads \"${SLURM_CPUS_PER_TASK:-0}\" --resume --quiet \\\n"
    << "    -o \"$WORK/shard-${SLURM_ARRAY_TASK_ID}\"\n";
  scripts.generate = g.str();

  std::ostringstream m;
  m << "#!/bin/bash\n"
    << "# Written by `lsds submit slurm` (lsds " << LSDS_VERSION
    << "); docs/scale-out.md explains it.\n"
    << "# Runs once every task of the array has succeeded (submit.sh gives "
       "it\n"
    << "# --dependency=afterok:<array>); joins the " << n
    << " shards into the collection one process\n"
    << "# would have written, checking that they cover every frame exactly "
       "once.\n"
    << "#SBATCH --job-name=" << job.job_name << "-merge\n"
    << ResourceLines(job, false) << "set -euo pipefail\n"
    << "LSDS=" << Q(job.lsds) << "\n"
    << "WORK=" << Q(job.work) << "\n"
    << "exec \"$LSDS\" merge \"$WORK\"/shard-{0.." << last << "} -o " << Q(job.output)
    << (job.force_merge ? " --force" : "") << " --quiet\n";
  scripts.merge = m.str();

  std::ostringstream s;
  s << "#!/bin/sh\n"
    << "# Written by `lsds submit slurm` (lsds " << LSDS_VERSION
    << "); docs/scale-out.md explains it.\n"
    << "# Submits the job array, then the merge: afterok makes the merge wait "
       "for every task to\n"
    << "# succeed; --kill-on-invalid-dep=yes cancels it when one fails "
       "(instead of leaving it\n"
    << "# pending forever). Arguments are passed to the merge's sbatch, e.g. "
       "--wait.\n"
    << "set -eu\n"
    << "WORK=" << Q(job.work) << "\n"
    << "mkdir -p \"$WORK/logs\"\n"
    // The logs go beside the shards; --output is given here rather than in
    // #SBATCH lines, which cannot hold a path with spaces.
    << "array=$(sbatch --parsable "
       "--output=\"$WORK/logs/generate-%A_%a.log\" \\\n"
    << "    \"$WORK/generate.sbatch\")\n"
    << "array=${array%%;*}  # --parsable prints jobid[;cluster]\n"
    << "echo \"generate: job array $array (" << n << " tasks)\"\n"
    << "exec sbatch --dependency=afterok:\"$array\" --kill-on-invalid-dep=yes "
       "\\\n"
    << "    --output=\"$WORK/logs/merge-%j.log\" \"$@\" "
    << "\"$WORK/merge.sbatch\"\n";
  scripts.submit = s.str();
  return scripts;
}

}  // namespace lsds
