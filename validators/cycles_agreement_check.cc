#include "validators/cycles_agreement_check.h"

#include <string>

namespace lsds::validate {
namespace {

Finding AgreementFinding(const std::string& key, const std::string& message) {
  Finding finding;
  finding.severity = Severity::kError;
  finding.check_id = kCyclesAgreementCheck;
  finding.location = Location(kCollectionFile, "/provenance/render/cycles_agreement/" + key);
  finding.message = message;
  return finding;
}

}  // namespace

std::vector<Finding> CyclesAgreementFindings(const CollectionHeader& header) {
  std::vector<Finding> findings;
  const nlohmann::json& render = header.provenance.render;
  if (!render.is_object() || !render.contains("cycles_agreement")) return findings;
  const nlohmann::json& agreement = render.at("cycles_agreement");
  const struct {
    const char* key;
    double tolerance;
    const char* what;
  } figures[] = {
      {"max_relative_depth_error",
       kMaxCyclesRelativeDepthError,
       "Cycles' depth pass differs from the depth layer"},
      {"max_id_mismatch_share",
       kMaxCyclesIdMismatchShare,
       "Cycles' object index pass names another object than the instanceid layer"},
  };
  for (const auto& figure : figures) {
    const nlohmann::json value =
        agreement.is_object() ? agreement.value(figure.key, nlohmann::json()) : nlohmann::json();
    if (!value.is_number()) {
      findings.push_back(AgreementFinding(
          figure.key, std::string("no number: the agreement of Cycles' passes is not recorded")));
      continue;
    }
    const double v = value.get<double>();
    if (!(v >= 0 && v <= figure.tolerance)) {
      const std::string frame_key = std::string(figure.key) + "_frame";
      const std::string frame =
          agreement.contains(frame_key) ? " (frame " + agreement.at(frame_key).dump() + ")" : "";
      findings.push_back(
          AgreementFinding(figure.key,
                           std::string(figure.what) + ": " + figure.key + " " + value.dump() +
                               frame + " exceeds " + std::to_string(figure.tolerance) +
                               "; the rgb does not show the geometry the truth describes"));
    }
  }
  return findings;
}

}  // namespace lsds::validate
