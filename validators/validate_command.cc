// lsds validate COLLECTION [--format text|json|junit] [-o REPORT]
//                          [--fail-on error|warning|info] [--checks LIST]
//                          [--frames A:B] [--threads N] [--max-examples N] [--force]
//                          [--shard I/N (writes a partial report to -o)]
#include <chrono>
#include <iostream>

#include "libs/collection/collection_guard.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "tools/command.h"
#include "tools/shared_flags.h"
#include "validators/report_writers.h"
#include "validators/validate.h"

namespace lsds {

int RunValidate(int argc, char** argv) {
  CLI::App app(
      "Check a collection before training: schemas, structure, every layer, "
      "cross-layer truth and "
      "camera geometry. Exit 0 when nothing is at or above --fail-on, 1 "
      "otherwise, 2 when the "
      "input cannot be read as a collection.",
      "lsds validate");
  std::string collection, format = "text", output, fail_on = "error", checks = "all";
  size_t max_examples = 20;
  app.add_option("COLLECTION", collection, "collection folder (holds collection.json)")->required();
  app.add_option("--format", format, "report format")
      ->check(CLI::IsMember({"text", "json", "junit"}));
  app.add_option(
      "-o,--output", output, "write the report to this file (atomically) instead of stdout");
  app.add_option("--fail-on", fail_on, "lowest severity that makes the run fail (exit 1)")
      ->check(CLI::IsMember({"error", "warning", "info"}));
  app.add_option("--checks",
                 checks,
                 "comma-separated check ids or groups (schema, structure, layer, "
                 "cross, camera, stats), or all; -ID excludes one (all,-camera; a list "
                 "that starts with -ID means all but it); default all");
  app.add_option(
         "--max-examples", max_examples, "findings kept and shown per check (all are counted)")
      ->check(CLI::PositiveNumber);
  CommonFlags common;
  AddCommonFlags(app, &common, "overwrite an existing report file");
  AddJobsAlias(app, &common);
  std::string shard;
  AddShardOption(app,
                 &shard,
                 "check only the frames whose index % N == I (I/N) and write a "
                 "partial report to -o; lsds merge-reports joins the N partial "
                 "reports into the report of a single run");
  return RunCommand(app, common, argc, argv, [&] {
    WarnIfJobsUsed(app);
    validate::Severity threshold;
    validate::ParseSeverity(fail_on, &threshold);
    validate::ValidateOptions options;
    options.checks = validate::CheckSelection::Parse(checks);
    options.jobs = common.threads;
    options.max_examples = max_examples;
    options.progress = true;  // on a terminal only; silent in CI and with -q
    OutputGuard guard("lsds validate");
    GuardCollection(&guard, collection, CollectionAccess::kReadOnly);
    guard.CheckOutput(output, "-o");
    if (!output.empty()) RefuseToOverwrite(output, common.force, "report");
    options.frames = SelectCollectionFrames(common.frames, collection);
    if (!shard.empty()) {
      ParseShard(shard, &options.shard_index, &options.shard_count);
      if (output.empty()) throw Error("--shard writes a partial report: give its file with -o");
      if (app.count("--format") > 0)
        throw Error(
            "--shard writes a partial report (JSON); --format applies "
            "to lsds merge-reports");
      const validate::PartialReport partial = validate::ValidateShard(collection, options);
      WriteFileAtomic(output, validate::PartialReportToJson(partial).dump(1) + "\n");
      if (!common.quiet)
        std::cerr << "lsds validate: shard " << shard << ": " << partial.report.frames
                  << " frame(s) checked -> " << output
                  << " (lsds merge-reports gives the verdict)\n";
      // The shard's job is done: the verdict needs every shard (exit 0 lets
      // the merge job of a Slurm array run).
      return kExitOk;
    }
    const auto start = std::chrono::steady_clock::now();
    validate::Report report;
    try {
      report = validate::ValidateCollection(collection, options);
    } catch (const Error& e) {
      // CI reads the JUnit file whatever the exit code: say why there is no
      // report of checks, then fail with exit 2 as usual.
      if (format == "junit" && !output.empty()) {
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        WriteFileAtomic(
            output,
            validate::UnreadableInputToJUnit(collection,
                                             e.location().ToString().empty()
                                                 ? e.message()
                                                 : e.location().ToString() + ": " + e.message(),
                                             seconds));
      }
      throw;
    }
    const std::string text = validate::RenderReport(report, format, threshold);
    if (output.empty()) {
      std::cout << text;
    } else {
      WriteFileAtomic(output, text);
      if (!common.quiet) std::cerr << validate::Verdict(report, threshold) << "\n";
    }
    return report.Fails(threshold) ? kExitFindings : kExitOk;
  });
}

}  // namespace lsds
