// What a collection's frames achieved of its LCAP requirements and quotas (docs/format.md,
// "Requirements"): frames met by estimate and in the rendered truth, and each quota's achieved
// count per bin. `lsds generate` prints it; `lsds validate` gates on it (requirements.*).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/collection/model.h"

namespace lsds {

struct RequirementSummary {
  int64_t frames = 0;           // frames with a demand
  int64_t attempts = 0;         // draws the planner estimated for them
  int64_t estimate_met = 0;     // frames whose kept draw met the demand by estimate
  int64_t achieved_met = 0;     // ... and in the rendered truth
  std::vector<int64_t> missed;  // frames whose truth missed the demand, in the order added
  // Per quota: its name and the achieved count per bin (the last slot: no bin).
  std::vector<std::pair<std::string, std::vector<int64_t>>> achieved;
  // A rig capture's unit is the time step: its frames are gathered here and counted once per step
  // by FoldSteps.
  struct Step {
    int64_t attempts = 1;
    bool estimate_met = false;
    int cameras = 0, cameras_met = 0;  // frames seen, frames whose truth met
    // Per quota: (demanded bin, achieved bin) of each camera.
    std::vector<std::vector<std::pair<size_t, size_t>>> bins;
  };
  std::map<int64_t, Step> steps;
};

// Adds one frame's record (`truth.requirements`) under what was asked (`asked`: the
// `provenance.requirements` of the collection, or a plan's `requirements`); nothing when null.
void AddRequirementSummary(const nlohmann::json& asked,
                           const Frame& truth,
                           RequirementSummary* summary);

// A rig capture's steps counted as the units of the summary: a step meets its demand when every
// camera's truth does (cameras:all) or one does (any); it counts in a quota's demanded bin when
// those cameras are in it, else in the first camera's bin.
RequirementSummary FoldSteps(const nlohmann::json& asked, const RequirementSummary& in);

// Joins the summary of other frames (another shard's) into `into`.
void MergeRequirementSummary(const RequirementSummary& other, RequirementSummary* into);

// The summary as partial validation reports carry it, and back (throws on a bad shape).
nlohmann::json RequirementSummaryToJson(const RequirementSummary& summary);
RequirementSummary RequirementSummaryFromJson(const nlohmann::json& json);

// The bin of quota `quota` (provenance form) a value falls in; the number of bins when none. A
// class quota's bins are its class ids.
size_t QuotaBinOf(const nlohmann::json& quota, double value);
// "bins [0,10,20]" or "classes ["car","truck"]".
std::string QuotaBinsText(const nlohmann::json& quota);

}  // namespace lsds
