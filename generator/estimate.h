// The cheap estimate behind LCAP requirements and quotas
// (generator/lang/requirements.h): a low-resolution ray cast of the target's
// id coverage with the same Embree scene the renderer builds, so that the
// planner can judge a draw before anything is rendered.
#pragma once

#include "generator/lang/requirements.h"

namespace lsds::gen {

// Rays per side of a target's projected box (at most; fewer for small boxes,
// one per pixel centre).
constexpr int kEstimateRaysPerSide = 32;

// Makes estimators that measure every target of a planned frame: visibility
// and occlusion from at most kEstimateRaysPerSide^2 pixel-centre rays inside
// the target's projected box (the hits on the target in the full scene over
// the hits in the target's own scene, as the truth defines visibility), the
// geometric quantities exactly (GeometricMeasures). Each estimator keeps its
// Embree scene while the world state does not change.
FrameEstimatorFactory MakeFrameEstimatorFactory();

// Statistics of every estimator made by this process (bench/).
struct EstimateStats {
  int64_t frames = 0;  // estimates made
  int64_t rays = 0;
  double seconds = 0;
};
EstimateStats GetEstimateStats();

}  // namespace lsds::gen
