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
// centres (Cycles' within 0.005 px): on pixels whose depth is smooth (within 5 %
// of its neighbours') their depths differ by float rounding and by at most
// 0.005 * 0.05 for the ray's offset; a wrong camera or transform moves them by
// percents.
inline constexpr double kMaxCyclesRelativeDepthError = 1e-3;
// Pixel-centre rays that graze an edge may land on either side of it.
inline constexpr double kMaxCyclesIdMismatchShare = 0.01;

std::vector<Finding> CyclesAgreementFindings(const CollectionHeader& header);

}  // namespace lsds::validate
