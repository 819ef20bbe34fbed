#include "generator/plan/plan.h"

#include <cmath>

namespace lsds {

double SunLuxFromIntensity(double intensity) {
  return intensity < kLegacySunIntensityLimit ? M_PI * intensity * kLegacyNitsPerUnit : intensity;
}

double RelativeLuminance(const Eigen::Vector3d& rgb) {
  return 0.2126 * rgb.x() + 0.7152 * rgb.y() + 0.0722 * rgb.z();
}

double SkyLuxPerZenithNit(const Eigen::Vector3d& color) {
  const double zenith = RelativeLuminance(color);
  if (!(zenith > 0)) return 0;
  const Eigen::Vector3d horizon_color = 0.5 * color + Eigen::Vector3d::Constant(kSkyHorizonWhite);
  const double horizon = RelativeLuminance(horizon_color) / zenith;  // per zenith cd/m^2
  // A uniform radiance L over the hemisphere gives a horizontal plane pi * L.
  return M_PI * (kSkyZenithWeight + kSkyHorizonWeight * horizon);
}

bool PlannedExposure::operator==(const PlannedExposure& o) const {
  return ev100 == o.ev100 && shutter_s == o.shutter_s && f_number == o.f_number && iso == o.iso &&
         compensation_ev == o.compensation_ev && focus_distance_m == o.focus_distance_m &&
         sensor_width_mm == o.sensor_width_mm;
}

bool PlannedEnvironment::operator==(const PlannedEnvironment& o) const {
  return sky.color == o.sky.color && sky.cloud_type == o.sky.cloud_type &&
         sky.cloud_density == o.sky.cloud_density && sky.luminance_cd_m2 == o.sky.luminance_cd_m2 &&
         sun.elevation_deg == o.sun.elevation_deg && sun.azimuth_deg == o.sun.azimuth_deg &&
         sun.illuminance_lux == o.sun.illuminance_lux && sun.clock_utc_s == o.sun.clock_utc_s &&
         sun.utc_offset_h == o.sun.utc_offset_h && fog_density == o.fog_density &&
         skylight_intensity == o.skylight_intensity && terrain_material == o.terrain_material &&
         terrain_shape == o.terrain_shape;
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
  plan->terrain = TerrainOf(*plan, e);
}

PlannedTerrain TerrainOf(const Plan& plan, const PlannedEnvironment& environment) {
  PlannedTerrain terrain = plan.terrain;
  const PlannedTerrainShape& shape = environment.terrain_shape;
  if (shape.perlin_amplitude) terrain.perlin_amplitude = *shape.perlin_amplitude;
  if (shape.perlin_frequency) terrain.perlin_frequency = *shape.perlin_frequency;
  return terrain;
}

PlannedTerrain TerrainAt(const Plan& plan, const PlannedFrame& frame) {
  return frame.environment ? TerrainOf(plan, *frame.environment) : plan.terrain;
}

bool TerrainShapeChanges(const Plan& plan) {
  for (const PlannedFrame& f : plan.frames)
    if (f.environment && !f.environment->terrain_shape.empty()) return true;
  return false;
}

}  // namespace lsds
