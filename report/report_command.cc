// lsds report COLLECTION -o report.html [--frames A:B] [--sample N]
// [--layer-frames K] [--validate | --validation-report FILE] [--bundle-stats FILE]
// [--evaluation FILE] [--force]
// (docs/report.md)
#include <filesystem>
#include <iostream>

#include "libs/collection/collection_guard.h"
#include "libs/collection/collection_reader.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "report/bundle_section.h"
#include "report/evaluation_section.h"
#include "report/report.h"
#include "tools/command.h"
#include "tools/shared_flags.h"
#include "validators/report_writers.h"
#include "validators/validate.h"

namespace lsds {

namespace {

// The sections made from other commands' JSON outputs (`lsds bundles -o`,
// `lsds evaluate -o`), each read and checked; empty paths: none.
void ReadJsonSections(const std::string& bundle_stats,
                      const std::string& evaluation,
                      report::ReportOptions* options) {
  if (!bundle_stats.empty()) {
    options->bundle_stats = ReadJsonFile(bundle_stats);
    report::CheckBundleStats(options->bundle_stats, bundle_stats);
  }
  if (!evaluation.empty()) {
    options->evaluation = ReadJsonFile(evaluation);
    report::CheckEvaluation(options->evaluation, evaluation);
  }
}

}  // namespace

int RunReport(int argc, char** argv) {
  CLI::App app(
      "One self-contained HTML page to look at a collection before training: "
      "contact sheet with the truth drawn on, every layer of a few frames, "
      "distributions, validation summary (docs/report.md).",
      "lsds report");
  report::ReportOptions options;
  std::string collection, output, validation_report, bundle_stats, evaluation, tonemap = "filmic";
  bool validate = false;
  app.add_option("COLLECTION", collection, "collection folder (holds collection.json)")->required();
  app.add_option("-o,--output", output, "the HTML file (written atomically)")->required();
  app.add_option("--sample", options.sample, "frames on the contact sheet, spread evenly")
      ->capture_default_str()
      ->check(CLI::Range(size_t{1}, size_t{10000}));
  app.add_option("--layer-frames", options.layer_frames, "of those, frames shown with every layer")
      ->capture_default_str();
  app.add_option(
         "--thumb-width", options.thumb_width, "contact sheet image width in px (never upscaled)")
      ->capture_default_str()
      ->check(CLI::Range(16, 4096));
  app.add_option("--layer-width", options.layer_width, "layer image width in px (never upscaled)")
      ->capture_default_str()
      ->check(CLI::Range(16, 4096));
  app.add_option("--exposure",
                 options.display.exposure_ev,
                 "exposure in EV for the colour images: linear * 2^EV")
      ->capture_default_str();
  app.add_option("--tonemap", tonemap, "filmic (ACES fit, default), reinhard or clamp")
      ->capture_default_str();
  app.add_flag("--validate",
               validate,
               "run lsds validate (all checks) and add its summary, with links "
               "from findings to their frames");
  app.add_option("--validation-report",
                 validation_report,
                 "add this `lsds validate --format json` report instead");
  app.add_option("--bundle-stats",
                 bundle_stats,
                 "add the class-mixing matrix and mixed pixels by object size "
                 "from this `lsds bundles -o` file");
  app.add_option("--evaluation",
                 evaluation,
                 "add the metrics, the worst strata and the coverage holes from this "
                 "`lsds evaluate -o` file");
  CommonFlags common;
  AddCommonFlags(app, &common, "replace an existing output file");
  return RunCommand(app, common, argc, argv, [&] {
    if (validate && !validation_report.empty()) {
      throw Error("--validate and --validation-report exclude each other",
                  Location("--validation-report"));
    }
    if (!imaging::ParseToneMap(tonemap, &options.display.tonemap)) {
      throw Error("expected filmic, reinhard or clamp, got '" + tonemap + "'",
                  Location("--tonemap"));
    }
    options.frames = SelectCollectionFrames(common.frames, collection);
    options.force = common.force;
    options.collection = collection;
    options.output = output;
    // The page never replaces one of its inputs, even with --force.
    OutputGuard guard("lsds report");
    // "Not a collection" says more than "the output lies inside the folder".
    CheckCollectionFolder(collection);
    GuardCollection(&guard, collection, CollectionAccess::kReadOnly);
    guard.AddInput(validation_report, "validation report");
    guard.AddInput(bundle_stats, "bundle statistics file");
    guard.AddInput(evaluation, "evaluation file");
    guard.CheckOutput(output, "-o");
    // Refuse before the long validation run, not after it.
    RefuseToOverwrite(output, options.force, "report");
    // The JSON inputs are read whole and typed before the long run: a
    // malformed one is refused at its line:column or JSON pointer.
    ReadJsonSections(bundle_stats, evaluation, &options);
    if (!validation_report.empty()) {
      options.validation =
          report::ParseValidationReport(ReadTextFile(validation_report), validation_report);
    } else if (validate) {
      validate::ValidateOptions validate_options;
      validate_options.progress = true;
      const validate::Report result = validate::ValidateCollection(collection, validate_options);
      options.validation = report::ReadValidationReport(
          validate::ReportToJson(result, validate::Severity::kError), "lsds validate");
      if (!common.quiet) std::cerr << validate::Verdict(result, validate::Severity::kError) << "\n";
    }
    const report::ReportResult result = report::WriteReport(options);
    if (!common.quiet)
      std::cout << "wrote " << output << " (" << result.frames << " frames, " << result.sampled
                << " on the contact sheet, " << (result.bytes + 512) / 1024 << " KiB)\n";
    // The page shows a broken file where its picture would be; say so here
    // too, so that a script reading only the terminal is not misled.
    if (!result.unshown.empty()) {
      std::cerr << "warning: " << result.unshown.size()
                << " picture(s) could not be shown; the first: " << result.unshown.front()
                << "\n(lsds validate names every problem)\n";
    }
    return kExitOk;
  });
}

}  // namespace lsds
