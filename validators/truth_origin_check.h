// `structure.truth-origin` (info): what an imported collection does not hold,
// read from provenance.import.truth_origin (docs/format.md, "Truth of other
// origins"), so that a user sees, before training on it, that the source had
// no shadow layer or bundles, or that visibility is an estimate. A collection
// lsds rendered has no provenance.import and no such finding.
#pragma once

#include <string>
#include <vector>

#include "libs/collection/model.h"
#include "validators/finding.h"

namespace lsds::validate {

inline constexpr const char* kTruthOriginCheck = "structure.truth-origin";

// One info finding per field the source could not provide ("absent") and per
// field lsds estimated rather than measured (a derived visibility); located
// at collection.json#/provenance/import/truth_origin/FIELD.
std::vector<Finding> TruthOriginFindings(const CollectionHeader& header);

}  // namespace lsds::validate
