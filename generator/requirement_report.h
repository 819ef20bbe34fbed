// What `lsds generate` reports of the requirements and quotas of a capture
// (docs/languages.md, "Requirements and quotas"): frames met by estimate and in
// the rendered truth, and each quota's achieved count per bin.
#pragma once

#include <string>

#include "generator/plan/plan.h"
#include "libs/collection/model.h"
#include "libs/collection/requirement_summary.h"

namespace lsds::gen {

// Adds one written frame to the summary (libs/collection/requirement_summary.h).
void AddRequirementSummary(const Plan& plan, const Frame& truth, RequirementSummary* summary);
// "requirements: 10/10 frames met (truth), ...; quota Q visibility: planned
// [5,5] achieved [5,5]" lines; empty without requirements.
std::string FormatRequirementSummary(const Plan& plan, const RequirementSummary& summary);

// What `lsds plan` prints: frames met by estimate, draws per frame, and per
// quota the planned count per bin and the bins the kept draws' estimates fall
// in; empty without requirements.
std::string FormatPlannedRequirements(const Plan& plan);

}  // namespace lsds::gen
