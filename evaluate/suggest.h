// `lsds evaluate --suggest NEXT.lcap` (docs/evaluate.md, "Suggesting the next
// capture"): the collection's LCAP capture with quotas that ask for more
// frames in the strata where the model did worst and in the empty cells
// inside the range the collection reaches; a quota the capture already has
// gets its weights raised where the model did worst instead.
#pragma once

#include <string>
#include <vector>

#include "evaluate/conditions.h"
#include "evaluate/evaluate_report.h"
#include "evaluate/ground_truth.h"

namespace lsds::evaluate {

struct Suggestion {
  std::string lcap;  // the capture text to write
  // The quota symbols added ("SUGGEST_SIZE_PX") or whose weights were raised
  // (the capture's own, "Q").
  std::vector<std::string> quotas;
};

// Throws lsds::Error (exit 2) when the collection records no LCAP capture in
// text notation (provenance.capture_source), which the suggestion extends.
Suggestion SuggestCapture(const EvaluationTruth& truth,
                          const std::vector<ConditionBins>& conditions,
                          const EvaluationReport& report);

}  // namespace lsds::evaluate
