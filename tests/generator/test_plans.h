// Small plans with analytic answers for the generator tests: flat terrain at z
// = 0 (class 1, instance 1000), optional boxes, nadir cameras.
#pragma once

#include <vector>

#include "generator/plan/plan.h"
#include "libs/geometry/rigid3.h"

namespace lsds::gen::testing {

inline Plan FlatPlan(int width = 64, int height = 48, double hfov_deg = 60) {
  Plan plan;
  plan.seed = 7;
  plan.classes = {{1, "ground"}, {2, "box"}};
  plan.terrain.present = true;
  plan.terrain.size = {400, 400};
  plan.terrain.perlin_amplitude = 0;
  plan.terrain.material = "sandy";
  plan.terrain.class_id = 1;
  plan.terrain.instance_id = 1000;
  plan.sun.elevation_deg = 60.0;
  plan.sun.azimuth_deg = 90.0;  // from the east (+x), 60 degrees up
  plan.sun.illuminance_lux = SunLuxFromIntensity(3.0);
  PlannedFrame frame;
  frame.camera = PinholeCamera::FromHorizontalFov(width, height, hfov_deg);
  frame.sequence = "P1(1)";
  plan.frames.push_back(frame);
  return plan;
}

// A nadir camera at `eye`: image x along world +x, image y along world -y.
inline Rigid3d Nadir(const Eigen::Vector3d& eye) {
  return LookAt(eye, eye - Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::UnitY());
}

inline PlannedObject Box(const std::string& name,
                         uint32_t instance_id,
                         const Eigen::Vector3d& centre,
                         const Eigen::Vector3d& extent) {
  PlannedObject o;
  o.name = name;
  o.symbol = name;
  o.class_name = "cube";
  o.class_id = 2;
  o.instance_id = instance_id;
  o.position = centre;
  o.extent = extent;
  return o;
}

}  // namespace lsds::gen::testing
