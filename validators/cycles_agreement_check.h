// `structure.cycles-agreement` (error): a collection whose rgb Blender Cycles
// rendered (`lsds generate --renderer cycles`) records in
// provenance.render.cycles_agreement how Cycles' own depth and object index
// passes agreed with lsds's depth and instanceid layers; the rgb shows the
// geometry the truth describes only when they agree within the tolerances
// below (docs/validate.md, docs/generator.md "Blender Cycles"). Collections
// without that record have no finding.
#pragma once

#include <vector>

#include "libs/collection/model.h"
#include "validators/finding.h"

namespace lsds::validate {

inline constexpr const char* kCyclesAgreementCheck = "structure.cycles-agreement";
// Cycles and Embree intersect the same float triangles through the same pixel
// centres: their depths differ by float rounding (a few 1e-6 relative).
inline constexpr double kMaxCyclesRelativeDepthError = 1e-4;
// Pixel-centre rays that graze an edge may land on either side of it.
inline constexpr double kMaxCyclesIdMismatchShare = 0.01;

std::vector<Finding> CyclesAgreementFindings(const CollectionHeader& header);

}  // namespace lsds::validate
