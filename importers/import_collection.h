// `lsds import`: a source of another simulator into a collection, through the
// one collection builder (libs/collection/collection_builder.h). The importer
// decodes; this driver derives what the source lacks (world position from
// depth and camera, per-object truth from the id layer and the OBB) and writes
// frame by frame into a temporary folder renamed at the end.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "importers/importer.h"

namespace lsds::import {

struct ImportResult {
  int64_t frames = 0;
  int64_t objects = 0;                // truth entries written, over all frames
  std::vector<std::string> warnings;  // the importer's (SourceDescription::warnings)
};

// Throws lsds::Error when the output exists (without `force`), is or lies
// inside the source or contains it, or the source is not what `format` claims.
// The source is only read.
ImportResult ImportCollection(const std::string& format,
                              const std::filesystem::path& source,
                              const std::filesystem::path& output,
                              const ImportOptions& options,
                              bool force);

}  // namespace lsds::import
