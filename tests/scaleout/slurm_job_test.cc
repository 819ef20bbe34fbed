// The text of the Slurm scripts `lsds submit slurm` writes.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "libs/util/error.h"
#include "scaleout/slurm_job.h"

namespace lsds {
namespace {

SlurmJob Job() {
  SlurmJob job;
  job.lsds = "/opt/lsds/bin/lsds";
  job.scene = "/data/field.lscene";
  job.capture = "/data/flight's plan.lcap";  // a quote and a space
  job.output = "/scratch/run";
  job.work = "/scratch/run.shards";
  job.shards = 8;
  job.seed = 42;
  job.spp = 4;
  job.frames = "0:800";
  return job;
}

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(SlurmScriptsTest, TheArrayRendersShardTaskIdOfNWithResume) {
  SlurmJob job = Job();
  job.throttle = 3;
  job.partition = "gpu";
  job.time = "2:00:00";
  job.cpus_per_task = 16;
  job.mem = "32G";
  const std::string g = MakeSlurmScripts(job).generate;
  EXPECT_EQ(g.rfind("#!/bin/bash\n", 0), 0u);
  EXPECT_TRUE(Has(g, "\n#SBATCH --array=0-7%3\n")) << g;
  EXPECT_TRUE(Has(g, "\n#SBATCH --partition=gpu\n"));
  EXPECT_TRUE(Has(g, "\n#SBATCH --time=2:00:00\n"));
  EXPECT_TRUE(Has(g, "\n#SBATCH --cpus-per-task=16\n"));
  EXPECT_TRUE(Has(g, "\n#SBATCH --mem=32G\n"));
  EXPECT_TRUE(Has(g, "--shard \"${SLURM_ARRAY_TASK_ID}/8\"")) << g;
  EXPECT_TRUE(Has(g, " --resume ")) << g;
  EXPECT_TRUE(Has(g, "--threads \"${SLURM_CPUS_PER_TASK:-0}\""));
  EXPECT_TRUE(Has(g, "-o \"$WORK/shard-${SLURM_ARRAY_TASK_ID}\""));
  EXPECT_TRUE(Has(g, "--seed 42 --spp 4 --frames '0:800'")) << g;
  // Paths are single-quoted for the shell, a quote inside written '\''.
  EXPECT_TRUE(Has(g, "'/data/field.lscene' '/data/flight'\\''s plan.lcap'")) << g;
  EXPECT_TRUE(Has(g, "LSDS='/opt/lsds/bin/lsds'\n"));
  // #SBATCH lines come before the first command, or Slurm ignores them.
  EXPECT_LT(g.rfind("#SBATCH"), g.find("set -euo pipefail"));
}

// --compact reaches every task's lsds generate, as the other generate flags do; without it the
// tasks write generate's default layouts.
TEST(SlurmScriptsTest, CompactIsPassedToEveryTasksGenerate) {
  SlurmJob job = Job();
  EXPECT_FALSE(Has(MakeSlurmScripts(job).generate, "--compact")) << MakeSlurmScripts(job).generate;
  job.compact = true;
  job.depth = "perspective";
  const std::string g = MakeSlurmScripts(job).generate;
  EXPECT_TRUE(Has(g, "--frames '0:800' --depth 'perspective' --compact \\\n    --shard ")) << g;
  EXPECT_FALSE(Has(MakeSlurmScripts(job).merge, "--compact"));
}

TEST(SlurmScriptsTest, TheMergeDependsOnTheWholeArrayAndDiesWithIt) {
  const SlurmScripts scripts = MakeSlurmScripts(Job());
  EXPECT_TRUE(Has(scripts.merge,
                  "exec \"$LSDS\" merge \"$WORK\"/shard-{0..7} -o "
                  "'/scratch/run' --quiet\n"))
      << scripts.merge;
  EXPECT_FALSE(Has(scripts.merge, "--array"));
  const std::string& s = scripts.submit;
  EXPECT_TRUE(Has(s, "array=$(sbatch --parsable")) << s;
  EXPECT_TRUE(Has(s, "\"$WORK/generate.sbatch\")")) << s;
  EXPECT_TRUE(Has(s, "sbatch --dependency=afterok:\"$array\" --kill-on-invalid-dep=yes")) << s;
  EXPECT_TRUE(Has(s, "\"$WORK/merge.sbatch\"\n")) << s;
  EXPECT_TRUE(Has(s, "mkdir -p \"$WORK/logs\""));
  // The default: no throttle, no resources the cluster did not ask for.
  EXPECT_TRUE(Has(scripts.generate, "\n#SBATCH --array=0-7\n"));
  EXPECT_FALSE(Has(scripts.generate, "--partition"));
  EXPECT_FALSE(Has(scripts.generate, "--mem"));
}

TEST(SlurmScriptsTest, BadSettingsAreRefused) {
  SlurmJob job = Job();
  job.shards = 1;
  EXPECT_THROW(MakeSlurmScripts(job), Error);
  job = Job();
  job.partition = "a b";  // would break the #SBATCH line
  EXPECT_THROW(MakeSlurmScripts(job), Error);
  job = Job();
  job.throttle = -1;
  EXPECT_THROW(MakeSlurmScripts(job), Error);
  job = Job();
  job.work = "/scratch/100%";  // Slurm would expand % in the log names
  EXPECT_THROW(MakeSlurmScripts(job), Error);
}

// A control character in an #SBATCH value reaches sbatch as part of the value
// (a carriage return from a script edited on Windows): every task would fail.
TEST(SlurmScriptsTest, ControlCharactersInSbatchValuesAreRefusedNamingTheFlag) {
  const std::pair<std::string SlurmJob::*, const char*> fields[] = {
      {&SlurmJob::mem, "--mem"},
      {&SlurmJob::time, "--time"},
      {&SlurmJob::partition, "--partition"},
      {&SlurmJob::account, "--account"},
      {&SlurmJob::job_name, "--job-name"}};
  for (const auto& [field, flag] : fields) {
    for (const char* bad : {"8G\r", "a\nb", "a\x01", "a\x7f"}) {
      SlurmJob job = Job();
      job.*field = bad;
      try {
        MakeSlurmScripts(job);
        ADD_FAILURE() << flag << " accepted a control character";
      } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(std::string(flag) + " '", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find("control characters"), std::string::npos) << e.what();
      }
    }
  }
}

TEST(SlurmScriptsTest, ShellQuoteSurvivesQuotes) {
  EXPECT_EQ(ShellQuote("a b"), "'a b'");
  EXPECT_EQ(ShellQuote("it's"), "'it'\\''s'");
  EXPECT_EQ(ShellQuote(""), "''");
}

}  // namespace
}  // namespace lsds
