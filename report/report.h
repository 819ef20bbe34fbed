// `lsds report`: one self-contained HTML page to look at a collection before
// training on it: a contact sheet with the truth drawn on, every layer of a few
// frames, the distributions, and the validation summary (docs/report.md).
//
// Frames are streamed once (bounded memory); the contact sheet is an even
// sample; only the sampled frames' layers are decoded for pictures.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/collection/collection_reader.h"
#include "libs/imaging/srgb_image.h"
#include "libs/util/frame_selection.h"
#include "report/distributions.h"
#include "report/frame_camera.h"
#include "report/validation_section.h"

namespace lsds::report {

struct ReportOptions {
  std::filesystem::path collection;
  std::filesystem::path output;  // the HTML file, written atomically
  FrameRange frames;             // the frames with index in this range
  size_t sample = 24;            // frames on the contact sheet
  size_t layer_frames = 4;       // of those, frames shown with every layer
  int thumb_width = 320;         // contact sheet image width, px (never upscaled)
  int layer_width = 320;         // layer image width, px (never upscaled)
  bool force = false;            // replace an existing output
  // A validation report (`lsds validate --format json`, read with
  // ReadValidationReport); none: no validation section. The frames its
  // findings point to join the contact sheet so that links have targets.
  std::optional<ValidationSummary> validation;
  // Statistics from `lsds bundles -o` (checked with CheckBundleStats); null:
  // no mixed-pixel section.
  nlohmann::json bundle_stats;
  // The report `lsds evaluate -o` writes (checked with CheckEvaluation); null:
  // no evaluation section.
  nlohmann::json evaluation;
  imaging::DisplayOptions display;
};

struct SampledFrame {
  Frame frame;
  FrameCamera camera;
};

struct ReportData {
  Distributions distributions;        // over every selected frame
  std::vector<SampledFrame> samples;  // contact sheet, in collection order
};

// Streams the selected frames once: distributions of every frame, an even
// sample of `options.sample` frames, plus the frames in `always`.
ReportData CollectReportData(const CollectionReader& reader,
                             const ReportOptions& options,
                             const std::set<int64_t>& always = {});

// The page. Decodes the layers of the sampled frames only. What could not be
// shown is a message on the page and a line in `problems` (frame order).
std::string RenderReportHtml(const CollectionReader& reader,
                             const ReportData& data,
                             const ReportOptions& options,
                             std::vector<std::string>* problems);

struct ReportResult {
  int64_t frames = 0;  // frames in the distributions
  size_t sampled = 0;  // frames on the contact sheet
  size_t bytes = 0;    // size of the page
  // "rgb of frame 0: <file>: <why>" for every picture the page could not show.
  std::vector<std::string> unshown;
};

// Checks the output (refuses an existing one without `force`, and one inside
// the collection), collects, renders and writes atomically. Throws lsds::Error.
ReportResult WriteReport(const ReportOptions& options);

}  // namespace lsds::report
