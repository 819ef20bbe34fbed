// The evaluation part of the page, from the JSON `lsds evaluate -o` writes
// (schemas/evaluate.schema.json): the metrics, the worst stratum of every
// condition, and the empty and thin coverage cells (docs/report.md).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "report/html_text.h"

namespace lsds::report {

// Throws lsds::Error naming `file` and the JSON pointer of the first issue
// when `evaluation` is not an lsds evaluate report.
void CheckEvaluation(const nlohmann::json& evaluation, const std::string& file);

// The HTML section (id "evaluation").
Html EvaluationSection(const nlohmann::json& evaluation);

}  // namespace lsds::report
