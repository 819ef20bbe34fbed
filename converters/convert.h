// `lsds convert`: a collection's truth into one or more target formats
// (docs/convert.md).
#pragma once

#include "converters/loss_report.h"
#include "converters/options.h"

namespace lsds::convert {

struct ConvertResult {
  LossReport loss;
  int64_t frames = 0;
  int64_t images_written = 0;
};

// Builds options.output atomically (a temporary folder renamed at the end; a
// non-empty output is refused without options.force) holding the formats, the
// shared images and loss_report.{txt,json}. Throws lsds::Error (bad options,
// unreadable collection, missing layers).
ConvertResult Convert(const ConvertOptions& options);

}  // namespace lsds::convert
