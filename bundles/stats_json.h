// JSON form of the bundle statistics (schemas/bundle-stats.schema.json,
// docs/bundles.md).
#pragma once

#include <nlohmann/json.hpp>

#include "bundles/bundle_stats.h"
#include "libs/collection/model.h"

namespace lsds::bundle {

inline constexpr const char* kStatsFormat = "lsds-bundle-stats";
inline constexpr const char* kStatsFormatVersion = "1.0";

// The figures of one frame or of the collection ("stats" in the schema).
// `header` names the classes.
nlohmann::json StatsToJson(const BundleStats& stats,
                           const StatsOptions& options,
                           const CollectionHeader& header);
// One entry per object: mixed share of its pixels over all analysed frames.
nlohmann::json ObjectsToJson(const BundleStats& stats);
nlohmann::json OptionsToJson(const StatsOptions& options);

}  // namespace lsds::bundle
