// What a UAV logs besides its pose, computed for a planned frame on the plan's
// terrain (docs/format.md, "metadata.json"): altitude above ground, ground
// sample distance, the image's ground footprint and, for a geo-referenced
// scene, latitude, longitude and altitude above mean sea level.
#pragma once

#include "generator/plan/plan.h"
#include "libs/collection/model.h"

namespace lsds::gen {

// Rays that meet no ground within this range give no GSD / footprint.
inline constexpr double kSurveyMaxRangeM = 10000;

// Fills the survey fields of `metadata` for `frame`.
void AddSurveyMetadata(const Plan& plan, const PlannedFrame& frame, MetadataFrame* metadata);

}  // namespace lsds::gen
