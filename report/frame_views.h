// The pictures of one sampled frame: its contact sheet card (the colour image
// with the truth drawn on, camera figures, scene state, objects table) and its
// layer strip (every layer side by side). Decodes that frame's files only.
#pragma once

#include <string>
#include <vector>

#include "libs/collection/collection_reader.h"
#include "report/html_text.h"
#include "report/report.h"

namespace lsds::report {

// `has_layers` tags the card as one whose layers the page shows. A picture
// that cannot be shown becomes a message on the page, and the same message
// (naming the file) is appended to `problems`.
Html FrameCard(const CollectionReader& reader,
               const SampledFrame& sample,
               bool has_layers,
               const ReportOptions& options,
               std::vector<std::string>* problems);

Html LayerStrip(const CollectionReader& reader,
                const SampledFrame& sample,
                const ReportOptions& options,
                std::vector<std::string>* problems);

// "12.35" with `digits` decimals, "n/a" for NaN and infinities.
std::string Fixed(double value, int digits);
// True when `frame` has a file for `layer` (which may be null).
bool HasFile(const Frame& frame, const LayerInfo* layer);

}  // namespace lsds::report
