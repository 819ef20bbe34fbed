// The small synthetic collection of the evaluate goldens (the README.md of tests/evaluate):
// twelve boxes from 5 to 104 pixels across in two classes, seen by six nadir
// frames at 12 to 24 m (one offset so that objects are cut by the border) and
// one oblique frame. Both the tests and the goldens' maker
// (evaluate_golden_collection, make_goldens.py) write it from here.
#pragma once

#include "libs/geometry/attitude.h"
#include "synth/synthetic_collection.h"

namespace lsds::testing {

inline synth::Spec EvaluateGoldenSpec() {
  synth::Spec spec;
  spec.width = 256;
  spec.height = 192;
  spec.hfov_deg = 60;
  spec.classes = {{1, "ground"}, {2, "box"}, {3, "crate"}};
  spec.layers = {"classid", "instanceid"};
  spec.samples_per_axis = 1;
  struct Placed {
    double x, y, half_x, half_y, yaw;
    uint32_t class_id;
  };
  const Placed placed[] = {{-5, 3, 0.15, 0.15, 0, 2},
                           {-3, 3, 0.3, 0.3, 0, 3},
                           {-1, 3, 0.5, 0.5, 0, 2},
                           {1.5, 3, 0.8, 0.8, 0, 3},
                           {5, 3.5, 1.2, 1.2, 20, 2},
                           {-4, -1, 2.2, 2.0, 0, 3},
                           {1.5, -0.5, 2.8, 2.2, 0, 2},
                           {5, -2.5, 0.25, 0.25, 0, 3},
                           {-1.5, -3.5, 0.6, 0.4, 0, 2},
                           {5.5, 0.5, 0.4, 0.4, 45, 3},
                           {-5.5, -3.8, 0.35, 0.35, 0, 2},
                           {2.5, -3.8, 0.7, 0.7, 0, 3}};
  uint32_t id = 1;
  for (const Placed& p : placed) {
    synth::Box box;
    box.class_id = p.class_id;
    box.instance_id = id;
    box.name = (p.class_id == 2 ? "box#" : "crate#") + std::to_string(id++);
    box.center = {p.x, p.y, 0.3};
    box.half_extents = {p.half_x, p.half_y, 0.3};
    box.yaw_deg = p.yaw;
    spec.boxes.push_back(box);
  }
  const Eigen::Vector3d nadir[] = {
      {0, 0, 12}, {3, 2, 12}, {1, 0.5, 14}, {-1, -0.5, 16}, {0.5, -1, 20}, {0, 0, 24}};
  for (const Eigen::Vector3d& position : nadir)
    spec.cam_from_world.push_back(synth::NadirCamFromWorld(position));
  // Looking north, 30 degrees off nadir.
  spec.cam_from_world.push_back(CamFromEnu({0, -8, 12}, Attitude{0.0, -60.0, 0.0}));
  return spec;
}

}  // namespace lsds::testing
