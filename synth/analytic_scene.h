// Exact ray casting against a ground plane and oriented boxes: the analytic
// truth that synthetic collections are made of (cf. COLMAP's synthetic
// dataset).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "libs/geometry/oriented_box.h"

namespace lsds::synth {

struct Box {
  uint32_t class_id = 2;
  uint32_t instance_id = 1;
  std::string name;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // world metres
  Eigen::Vector3d half_extents = Eigen::Vector3d::Ones();
  double yaw_deg = 0;  // rotation about +z

  OrientedBox Obb() const;
};

struct Hit {
  bool hit = false;
  double t = 0;  // ray parameter: point = origin + t * direction
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  uint32_t class_id = 0;
  uint32_t instance_id = 0;
};

struct AnalyticScene {
  bool ground = true;  // the plane z = 0
  uint32_t ground_class_id = 1;
  uint32_t ground_instance_id = 1000;
  std::vector<Box> boxes;

  // Closest hit with t > t_min. `only_box` >= 0 restricts the scene to that box
  // (unoccluded renders).
  Hit Intersect(const Eigen::Vector3d& origin,
                const Eigen::Vector3d& direction,
                double t_min = 1e-9,
                int only_box = -1) const;
};

}  // namespace lsds::synth
