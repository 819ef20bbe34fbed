// JSON form of the frame plan (schemas/plan.schema.json). Rotations are 3x3
// row-major matrices and poses `{rotation, translation}` as in the collection
// format (docs/format.md).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "generator/plan/plan.h"

namespace lsds {

inline constexpr const char* kPlanFormat = "lsds-plan";
inline constexpr const char* kPlanFormatVersion = "1.0";

nlohmann::json PlanToJson(const Plan& plan);
// Validates against plan.schema.json first; errors name `file` and the JSON
// pointer.
Plan PlanFromJson(const nlohmann::json& json, const std::string& file);

nlohmann::json PlannedFrameToJson(const PlannedFrame& frame);
// One scene change as the plan writes it ({"object": ..., "extent": ...}).
nlohmann::json ObjectChangeToJson(const ObjectChange& change);
// The camera exposure of a plan (`exposure`: mode, ev100, shutter_s, f_number,
// iso, compensation_ev).
nlohmann::json ExposureToJson(const PlannedExposure& exposure);
PlannedExposure ExposureFromJson(const nlohmann::json& json);
PlannedFrame PlannedFrameFromJson(const nlohmann::json& json,
                                  const std::string& file,
                                  const std::string& pointer);

}  // namespace lsds
