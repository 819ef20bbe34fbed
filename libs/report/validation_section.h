// The validation summary of the page, from an `lsds validate --format json`
// report (schemas/validate-report.schema.json): verdict, counts, and per check
// the findings kept, each linked to its frame's card when the frame is on the
// contact sheet.
#pragma once

#include <cstdint>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

namespace lsds::report {

std::string ValidationSection(const nlohmann::json& validation,
                              const std::set<int64_t>& frames_on_sheet);

}  // namespace lsds::report
