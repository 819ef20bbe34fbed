// lsds submit slurm SCENE [CAPTURE] -o OUT --shards N [--submit [--wait]]:
// writes (and submits) the Slurm job array and merge job of a sharded
// generate run (scaleout/slurm_job.h writes the scripts).
#include <sys/stat.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>

#include "generator/generate.h"
#include "generator/plan_source.h"
#include "libs/collection/collection_reader.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/output_guard.h"
#include "scaleout/slurm_job.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;

// Writes `text` to `path` unless the same text is there: submitting again the
// same run (to finish failed tasks with --resume) needs no --force, a
// different run in the same folder does.
void WriteScript(const fs::path& path, const std::string& text, bool force) {
  if (fs::exists(path)) {
    if (ReadFile(path) == text) return;
    RefuseToOverwrite(path, force, "script of another run");
  }
  WriteFileAtomic(path, text);
  ::chmod(path.c_str(), 0755);
}

}  // namespace

// The flag declarations, one statement per flag (docs/architecture.md, "Long functions").
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
int RunSubmit(int argc, char** argv) {
  CLI::App app{
      "Write (and with --submit, submit) a Slurm job array that renders a "
      "run in N shards and a merge job that joins them",
      "lsds submit"};
  std::string scheduler, scene, capture, output, work, lsds_binary;
  std::optional<uint64_t> seed;
  std::optional<int> spp;
  std::string depth;
  SlurmJob job;
  bool submit = false, wait = false;
  app.add_option("SCHEDULER", scheduler, "slurm (the only one so far)")->required();
  app.add_option("SCENE", scene, "LSCENE file (text or JSON)")->required();
  app.add_option("CAPTURE", capture, "LCAP file (text or JSON)");
  app.add_option("-o,--output", output, "the merged collection folder")->required();
  app.add_option("--shards", job.shards, "N: tasks of the array (>= 2)")->required();
  app.add_option("--work-dir", work, "shards, logs and scripts (default: OUT.shards beside OUT)");
  app.add_option("--seed", seed, "random seed (as lsds generate)");
  app.add_option("--spp", spp, "samples per pixel (as lsds generate)");
  app.add_option("--depth", depth, "planar or perspective (as lsds generate)");
  app.add_flag("--compact",
               job.compact,
               "store worldposition and motion in their lossless residual layouts (as lsds "
               "generate --compact; lsds merge keeps them)");
  app.add_option("--partition", job.partition, "Slurm partition");
  app.add_option("--account", job.account, "Slurm account");
  app.add_option("--time", job.time, "time limit per task, e.g. 2:00:00");
  app.add_option("--cpus-per-task", job.cpus_per_task, "CPUs per task (its render threads)");
  app.add_option("--mem", job.mem, "memory per task, e.g. 8G");
  app.add_option("--throttle", job.throttle, "at most K tasks run at once (array %K)");
  app.add_option("--job-name", job.job_name, "job name prefix (default lsds)");
  app.add_option("--lsds", lsds_binary, "the lsds binary the jobs run (default: this one)");
  app.add_flag("--submit", submit, "submit with sbatch after writing");
  app.add_flag("--wait",
               wait,
               "with --submit: wait for the merge; exit 1 if a task or the "
               "merge failed");
  CommonFlags common;
  AddCommonFlags(app,
                 &common,
                 "replace other scripts in the work folder and an existing output",
                 {{"--threads",
                   "each task renders with the CPUs Slurm gives it: set them with "
                   "--cpus-per-task"}});
  return RunCommand(app, common, argc, argv, [&]() {
    if (scheduler != "slurm")
      throw Error("unknown scheduler '" + scheduler +
                  "': only slurm (docs/scale-out.md shows a Kubernetes "
                  "Indexed Job)");
    if (wait && !submit) throw Error("--wait needs --submit");
    job.scene = fs::absolute(scene).lexically_normal();
    if (!capture.empty()) job.capture = fs::absolute(capture).lexically_normal();
    job.output = fs::absolute(output).lexically_normal();
    job.work = work.empty() ? fs::path(job.output.string() + ".shards")
                            : fs::absolute(work).lexically_normal();
    job.lsds = lsds_binary.empty() ? fs::read_symlink("/proc/self/exe") : fs::absolute(lsds_binary);
    job.seed = seed;
    job.spp = spp;
    job.frames = common.frames;
    job.depth = depth;
    job.force_merge = common.force;
    job.Check();
    // Every value the tasks pass to lsds generate goes through generate's own
    // checks here: a bad one fails now, not in each of N tasks on the cluster.
    gen::GenerateOptions task;
    task.output = job.work / "shard-0";
    task.shard_count = job.shards;
    if (spp) task.spp = *spp;
    if (!depth.empty()) task.depth_kind = ParseDepthFlag(depth);
    if (job.compact) task.layouts.UseCompact();
    task.Check();
    // The plan is made here so that a bad scene or too many shards fail now,
    // not in every task on the cluster.
    const Plan plan = gen::PlanFromScene(scene, capture, seed.value_or(0), FramesFlag(common));
    if (static_cast<int64_t>(plan.frames.size()) < job.shards)
      throw Error("--shards " + std::to_string(job.shards) + ": the run has " +
                  std::to_string(plan.frames.size()) + " frames; every shard needs at least one");
    OutputGuard guard("lsds submit");
    guard.AddInput(scene, "scene file");
    guard.AddInput(capture, "capture file");
    guard.CheckOutput(job.output, "-o");
    for (const char* script : {"generate.sbatch", "merge.sbatch", "submit.sh"})
      guard.CheckOutput(job.work / script, "--work-dir");
    if (fs::exists(job.output)) RefuseToOverwrite(job.output, common.force);
    const SlurmScripts scripts = MakeSlurmScripts(job);
    fs::create_directories(job.work / "logs");
    WriteScript(job.work / "generate.sbatch", scripts.generate, common.force);
    WriteScript(job.work / "merge.sbatch", scripts.merge, common.force);
    WriteScript(job.work / "submit.sh", scripts.submit, common.force);
    if (!common.quiet)
      std::cerr << "lsds submit: " << plan.frames.size() << " frames in " << job.shards
                << " shards; scripts in " << job.work.string() << "\n";
    if (!submit) {
      std::cerr << "submit with: sh " << ShellQuote((job.work / "submit.sh").string()) << "\n";
      return kExitOk;
    }
    // NOLINTNEXTLINE(concurrency-mt-unsafe): the command is single-threaded here
    if (std::system("command -v sbatch >/dev/null 2>&1") != 0)
      throw Error("sbatch not found on PATH: submit from a Slurm login node");
    std::cout.flush();
    // NOLINTNEXTLINE(concurrency-mt-unsafe): the command is single-threaded here
    const int status = std::system(
        ("sh " + ShellQuote((job.work / "submit.sh").string()) + (wait ? " --wait" : "")).c_str());
    bool ok = status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
    // sbatch --wait exits 0 for a merge that Slurm cancelled because a task
    // failed (its exit code is 0:0): success is the merged collection.
    if (wait && !LooksLikeCollection(job.output)) ok = false;
    if (!ok) {
      std::cerr << "lsds submit: "
                << (wait ? "the run failed (a task or the merge); the merge "
                           "never runs after a failed task"
                         : "sbatch failed")
                << "; logs in " << (job.work / "logs").string() << "\n";
      return wait ? kExitFindings : kExitUsage;
    }
    if (wait) std::cerr << "lsds submit: merged -> " << job.output.string() << "\n";
    return kExitOk;
  });
}

}  // namespace lsds
