// What `lsds generate` reports of the requirements and quotas of a capture
// (docs/languages.md, "Requirements and quotas"): frames met by estimate and in
// the rendered truth, and each quota's achieved count per bin.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "generator/plan/plan.h"
#include "libs/collection/model.h"

namespace lsds::gen {

// Requirements and quotas over the frames written (docs/languages.md).
struct RequirementSummary {
  int64_t frames = 0;           // frames with a demand
  int64_t attempts = 0;         // draws the planner estimated for them
  int64_t estimate_met = 0;     // frames whose kept draw met the demand by estimate
  int64_t achieved_met = 0;     // ... and in the rendered truth
  std::vector<int64_t> missed;  // frames whose truth missed the demand
  // Per quota: its name and the achieved count per bin (-1 index: no bin).
  std::vector<std::pair<std::string, std::vector<int64_t>>> achieved;
  // A rig capture's unit is the time step: its frames are gathered here and
  // counted once per step when the summary is formatted.
  struct Step {
    int64_t attempts = 1;
    bool estimate_met = false;
    int cameras = 0, cameras_met = 0;  // frames seen, frames whose truth met
    // Per quota: (demanded bin, achieved bin) of each camera.
    std::vector<std::vector<std::pair<size_t, size_t>>> bins;
  };
  std::map<int64_t, Step> steps;
};
// Adds one written frame to the summary.
void AddRequirementSummary(const Plan& plan, const Frame& truth, RequirementSummary* summary);
// "requirements: 10/10 frames met (truth), ...; quota Q visibility: planned
// [5,5] achieved [5,5]" lines; empty without requirements.
std::string FormatRequirementSummary(const Plan& plan, const RequirementSummary& summary);

// What `lsds plan` prints: frames met by estimate, draws per frame, and per
// quota the planned count per bin and the bins the kept draws' estimates fall
// in; empty without requirements.
std::string FormatPlannedRequirements(const Plan& plan);

}  // namespace lsds::gen
