#include "validators/truth_origin_check.h"

#include "libs/collection/model.h"

namespace lsds::validate {

std::vector<Finding> TruthOriginFindings(const CollectionHeader& header) {
  std::vector<Finding> findings;
  const nlohmann::json& import = header.provenance.import;
  if (!import.is_object() || !import.contains("truth_origin") ||
      !import.at("truth_origin").is_object())
    return findings;
  const std::string format = import.value("format", std::string("?"));
  for (const auto& [field, origin] : import.at("truth_origin").items()) {
    if (!origin.is_string()) continue;  // the schema check reports it
    std::string message;
    if (origin == "absent") {
      message = "'" + field + "' is absent: the " + format +
                " source does not provide it, so commands that need it "
                "(e.g. bundles for `lsds bundles`, shadow for shadow "
                "statistics) have nothing to read";
    } else if (origin == "derived" && field == "visibility") {
      message =
          "'visibility' is estimated: derived from the object's OBB (the "
          "unoccluded pixels are those whose ray enters the box), exact for "
          "box-shaped objects and a lower bound otherwise";
    } else {
      continue;
    }
    Finding finding;
    finding.severity = Severity::kInfo;
    finding.check_id = kTruthOriginCheck;
    finding.location = Location(
        kCollectionFile,
        (nlohmann::json::json_pointer("/provenance/import/truth_origin") / field).to_string());
    finding.message = message;
    findings.push_back(std::move(finding));
  }
  return findings;
}

}  // namespace lsds::validate
