#include "generator/plan/plan.h"

namespace lsds {

bool PlannedEnvironment::operator==(const PlannedEnvironment& o) const {
  return sky.color == o.sky.color && sky.cloud_type == o.sky.cloud_type &&
         sky.cloud_density == o.sky.cloud_density && sky.intensity == o.sky.intensity &&
         sun.elevation_deg == o.sun.elevation_deg && sun.azimuth_deg == o.sun.azimuth_deg &&
         sun.intensity == o.sun.intensity && sun.clock_utc_s == o.sun.clock_utc_s &&
         sun.utc_offset_h == o.sun.utc_offset_h && fog_density == o.fog_density &&
         skylight_intensity == o.skylight_intensity && terrain_material == o.terrain_material;
}

PlannedEnvironment EnvironmentOf(const Plan& plan) {
  PlannedEnvironment e;
  e.sky = plan.sky;
  e.sun = plan.sun;
  e.fog_density = plan.fog_density;
  e.skylight_intensity = plan.skylight_intensity;
  e.terrain_material = plan.terrain.material;
  return e;
}

PlannedEnvironment EnvironmentAt(const Plan& plan, const PlannedFrame& frame) {
  return frame.environment ? *frame.environment : EnvironmentOf(plan);
}

void SetEnvironment(const PlannedEnvironment& e, Plan* plan) {
  plan->sky = e.sky;
  plan->sun = e.sun;
  plan->fog_density = e.fog_density;
  plan->skylight_intensity = e.skylight_intensity;
  plan->terrain.material = e.terrain_material;
}

}  // namespace lsds
