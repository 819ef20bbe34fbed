// LCAP requirements and quotas (docs/languages.md, "Requirements and quotas"):
// per-frame bounds on how a target is seen (`require{...}`, hard or soft) and
// target distributions over the collection (`quota{...}`). The planner redraws
// a frame's free variables until its estimate meets them, within a budget.
// Measuring is left to a FrameEstimator the caller supplies (the generator's
// Embree ray cast), so this library stays free of the renderer.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "generator/lang/scene.h"
#include "generator/plan/plan.h"
#include "libs/collection/model.h"

namespace lsds {

// The quantities a requirement or quota may bound. Per target: visibility,
// occlusion (1 - visibility), in_frame, size_px (larger side of the projected
// box clipped to the image), gsd (metres per pixel at the target), distance
// (m, camera centre to box centre), view_angle (deg between the line of sight
// and the vertical: 0 = seen from straight above), class (the class id the
// target is drawn with: quota only, bins are class names). Per frame: altitude
// (m above the terrain under the camera), off_nadir (deg of the optical axis
// from straight down), sun_elevation (deg above the horizon), time_of_day
// (local hours of the sun's clock; only for a sun given by date and time).
const std::vector<std::string>& RequirementQuantities();
bool IsFrameQuantity(const std::string& quantity);

// How one target object is seen in one frame.
struct TargetMeasure {
  std::string object;                    // PlannedObject::name
  std::map<std::string, double> values;  // quantity -> value
};

// Everything measured on a frame: its targets and the frame quantities.
struct FrameMeasure {
  std::vector<TargetMeasure> targets;
  std::map<std::string, double> frame;
};

// The geometric quantities of an object box seen by a camera (everything but
// visibility and occlusion).
std::map<std::string, double> GeometricMeasures(const OrientedBox& box,
                                                const PinholeCamera& camera,
                                                const Rigid3d& cam_from_world);
// The frame quantities (altitude above the terrain, off-nadir angle, the sun's
// elevation and the local time of day when the sun has a clock).
std::map<std::string, double> FrameMeasures(const Plan& plan, const PlannedFrame& frame);
// Measures from rendered truth: the achieved values of a frame.
FrameMeasure MeasureTruth(const Plan& plan,
                          const PlannedFrame& frame,
                          const std::vector<ObjectTruth>& objects);

// Cheap estimate of a planned frame (the plan's world and terrain are final).
// Called with frames the planner has not kept yet.
using FrameEstimator = std::function<FrameMeasure(const Plan& plan, const PlannedFrame& frame)>;
using FrameEstimatorFactory = std::function<FrameEstimator()>;

struct Bound {
  std::string quantity;
  double lo = 0, hi = 0;  // inclusive
};

struct Requirement {
  std::string name;           // the LCAP symbol
  std::string target;         // object symbol; empty for frame quantities only
  std::vector<Bound> bounds;  // all must hold
  double probability = 1;     // < 1: soft, enforced on this share of frames
};

struct Quota {
  std::string name;
  std::string target;  // empty for frame quantities and for a class quota over every target
  std::string quantity;
  std::vector<double> edges;    // bin i = [edges[i], edges[i+1]) (last bin closed)
  std::vector<double> weights;  // target share of each bin, normalised
  double tolerance = 0.05;      // allowed |achieved - target| share per bin
  // A class quota (quantity:class): bin i is the class classes[i], whose id
  // (class_ids[i]) ResolveQuotaClasses finds in the plan's class table.
  std::vector<std::string> classes;
  std::vector<double> class_ids;
  Node classes_node;  // for messages
  // Importance sampling (docs/languages.md): the free variable that sets the
  // quantity is drawn within the frame's bin where the capture allows it.
  bool importance = true;
  bool categorical() const { return !classes.empty(); }
  size_t bins() const { return weights.size(); }
};

// The requirements and quotas of a capture, checked (keys, targets, bounds).
struct RequirementSet {
  std::vector<Requirement> requirements;
  std::vector<Quota> quotas;
  int budget = 50;  // redraws per frame before giving up
  // With a camera rig, whether every camera of a step (all) or at least one
  // (any) must meet the step's demand.
  bool rig_any = false;
  bool fail_on_budget = false;  // on_budget:fail makes a missed frame a plan error
  bool empty() const { return requirements.empty() && quotas.empty(); }
};
RequirementSet ReadRequirements(const Program& capture, const Program& scene);
// Class quotas: the ids of their class names in the plan's class table (after
// the capture's class swaps joined it); an unknown name is a located error.
void ResolveQuotaClasses(const std::vector<ClassInfo>& classes, RequirementSet* set);
bool IsRequirementKind(const std::string& kind);
void CheckRequirementDefinition(const Definition& d);

// What frame k must satisfy: the soft requirements drawn in (stream (seed,
// frame k)), and its stratum of every quota. Depends only on (seed, k, total
// frames), so shards plan the same demands.
struct FrameDemand {
  std::vector<const Requirement*> active;
  std::vector<std::pair<const Quota*, int>> bins;  // quota, bin index
};
class DemandPlanner {
 public:
  DemandPlanner(const RequirementSet& set, uint64_t seed, int64_t total_frames);
  FrameDemand For(int64_t k) const;
  // The planned number of frames per bin of quota q.
  std::vector<int64_t> PlannedCounts(size_t q) const;

 private:
  const RequirementSet& set_;
  uint64_t seed_;
  std::vector<std::vector<int>> bin_of_frame_;  // per quota
};

// Sum of how far each demanded value lies outside its bounds (0: met). A target
// that is not measured (out of view) counts as a violation of 1 per bound.
double Violation(const FrameDemand& demand, const FrameMeasure& measure);
int QuotaBin(const Quota& quota, double value);  // -1 when outside every bin
// The [lo, hi] a frame's bin of a quota allows (hi exclusive but for the last
// bin; lo == hi == the class id for a class quota).
std::pair<double, double> BinRange(const Quota& quota, int bin);

// The frame's record (plan and collection): attempts, whether it is met, and
// the values of every demanded quantity.
nlohmann::json DemandRecord(const FrameDemand& demand, const FrameMeasure& measure);

// The planned record with the values achieved in the rendered truth added to
// every check ("achieved", "achieved_met") and to the frame ("achieved_met").
nlohmann::json AchievedRecord(const nlohmann::json& planned, const FrameMeasure& achieved);

// provenance.requirements: what was asked and the planned counts per bin.
nlohmann::json RequirementsProvenance(const RequirementSet& set, const DemandPlanner& planner);

}  // namespace lsds
