// lsds merge-reports PARTIAL... [--format text|json|junit] [-o REPORT]
//                              [--fail-on error|warning|info] [--force]
// Joins the partial reports of `lsds validate --shard I/N` (validators/
// partial_report.h does the work) into the report of a single run.
#include <iostream>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/output_guard.h"
#include "tools/command.h"
#include "validators/partial_report.h"
#include "validators/report_writers.h"

namespace lsds {

int RunMergeReports(int argc, char** argv) {
  CLI::App app(
      "Join the partial reports of lsds validate --shard I/N into the report "
      "a single lsds validate run writes. Exit 0 when nothing is at or above "
      "--fail-on, 1 otherwise, 2 when the partial reports are not the N "
      "shards of one run.",
      "lsds merge-reports");
  std::vector<std::string> partials;
  std::string format = "text", output, fail_on = "error";
  app.add_option(
         "PARTIAL", partials, "partial reports (lsds validate --shard I/N -o FILE), any order")
      ->required();
  app.add_option("--format", format, "report format")
      ->check(CLI::IsMember({"text", "json", "junit"}));
  app.add_option(
      "-o,--output", output, "write the report to this file (atomically) instead of stdout");
  app.add_option("--fail-on", fail_on, "lowest severity that makes the run fail (exit 1)")
      ->check(CLI::IsMember({"error", "warning", "info"}));
  CommonFlags common;
  AddCommonFlags(app,
                 &common,
                 "overwrite an existing report file",
                 {{"--frames",
                   "the partial reports hold the frames each shard checked; select frames "
                   "with lsds validate --frames"}});
  return RunCommand(app, common, argc, argv, [&] {
    validate::Severity threshold;
    validate::ParseSeverity(fail_on, &threshold);
    std::vector<std::filesystem::path> files(partials.begin(), partials.end());
    if (!output.empty()) {
      OutputGuard guard("lsds merge-reports");
      for (const std::filesystem::path& file : files) guard.AddInput(file, "partial report");
      guard.CheckOutput(output, "-o");
      RefuseToOverwrite(output, common.force, "report");
    }
    const validate::Report report = validate::MergePartialReports(files);
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
