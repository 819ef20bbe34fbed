// `lsds convert`: a collection's truth into one or more target formats
// (docs/convert.md).
#pragma once

#include <memory>
#include <vector>

#include "converters/converter.h"
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

// The same with `also` run beside the formats of options.formats in the same
// pass (after them, on the same kept objects): for a reader of the
// converters' own choices (`lsds evaluate`'s oriented-box truth).
ConvertResult Convert(const ConvertOptions& options, std::vector<std::unique_ptr<Converter>> also);

}  // namespace lsds::convert
