// lsds check-export FORMAT DIR [--consumer NAME] [--classes LIST]
//                              [--format text|json|junit] [-o FILE] [--force]
#include <iostream>

#include "converters/check/registry.h"
#include "converters/check/report_writers.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tools/command.h"

namespace lsds {

int RunCheckExport(int argc, char** argv) {
  CLI::App app("Read an export folder as its consumers do (" + Join(check::CheckedFormats(), ", ") +
                   ") and report every image, label line, box or frame one of them would drop or "
                   "reject. Exit 0 when nothing is, 1 otherwise, 2 when the folder cannot be read.",
               "lsds check-export");
  std::string format, dir, consumer, classes, report_format = "text", output;
  app.add_option("FORMAT", format, "the lsds convert format of the export")->required();
  app.add_option("DIR", dir, "the export folder (lsds convert -o)")->required();
  app.add_option("--consumer",
                 consumer,
                 "apply one consumer's rules only (default: every consumer of FORMAT)");
  app.add_option("--classes",
                 classes,
                 "comma-separated class names a DOTA consumer is configured with (default: "
                 "DOTA v1.0's 15)");
  app.add_option("--format", report_format, "report format")
      ->check(CLI::IsMember({"text", "json", "junit"}));
  app.add_option("-o,--output", output, "write the report to this file (atomically)");
  CommonFlags common;
  AddCommonFlags(app,
                 &common,
                 "overwrite an existing report file",
                 {{"--frames",
                   "an export has no lsds frame indices: check-export reads every image of it "
                   "(export part of a collection with lsds convert --frames)"}});
  return RunCommand(app, common, argc, argv, [&] {
    check::CheckOptions options;
    if (!classes.empty()) options.dota_classes = Split(classes, ',');
    if (!output.empty()) RefuseToOverwrite(output, common.force, "report");
    const check::ExportReport report = check::CheckExport(format, dir, consumer, options);
    const std::string text = check::RenderReport(report, report_format);
    if (output.empty()) {
      std::cout << text;
    } else {
      WriteFileAtomic(output, text);
      if (!common.quiet) std::cerr << check::Verdict(report) << "\n";
    }
    return report.Fails() ? kExitFindings : kExitOk;
  });
}

}  // namespace lsds
