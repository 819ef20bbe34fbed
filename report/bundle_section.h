// The mixed-pixel part of the page, from the statistics `lsds bundles -o`
// writes (schemas/bundle-stats.schema.json): the class-mixing matrix and the
// mixed-pixel share by object size. Decoding every bundle again would cost as
// much as `lsds bundles` itself, so the report reads its output instead.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "libs/collection/model.h"
#include "report/html_text.h"

namespace lsds::report {

// Throws lsds::Error naming `file` when `stats` is not an lsds bundle
// statistics file with a summary holding class_mixing and by_object_size.
void CheckBundleStats(const nlohmann::json& stats, const std::string& file);

// The HTML section. Matrix rows are the class a sample belongs to, columns the
// class it shares pixels with (the diagonal: samples in pixels holding no other
// class); each cell shows the samples and their share of the row.
Html BundleStatsSection(const nlohmann::json& stats, const CollectionHeader& header);

}  // namespace lsds::report
