// `lsds evaluate --suggest NEXT.lcap` (docs/evaluate.md, "Suggesting the next
// capture"): the collection's LCAP capture with quotas that ask for more
// frames in the strata where the model did worst and in the empty cells
// inside the range the collection reaches.
#pragma once

#include <string>
#include <vector>

#include "evaluate/conditions.h"
#include "evaluate/evaluate_report.h"
#include "evaluate/ground_truth.h"

namespace lsds::evaluate {

struct Suggestion {
  std::string lcap;                 // the capture text to write
  std::vector<std::string> quotas;  // the quota symbols added ("SUGGEST_SIZE_PX")
};

// Throws lsds::Error (exit 2) when the collection records no LCAP capture in
// text notation (provenance.capture_source), which the suggestion extends.
Suggestion SuggestCapture(const EvaluationTruth& truth,
                          const std::vector<ConditionBins>& conditions,
                          const EvaluationReport& report);

}  // namespace lsds::evaluate
