// LCAP: camera, paths, collections and scene changes, expanded into the frames
// of a plan. The evaluator composes the units of generator/lang/capture/: the
// camera setup, its paths, the timeline, the scene change rules, the class
// swaps, the placement kept across changes, the clearance check and the
// quota redraws.
#pragma once

#include "generator/lang/requirements.h"
#include "generator/lang/scene.h"
#include "generator/plan/plan.h"

namespace lsds {

// Checks the whole capture (keys, references, values), then fills plan->frames
// for the global frame indices [begin, end) (end < 0: all), plan->post_process
// and plan->capture_settings. The world (plan objects, terrain) must already be
// sampled. Requirements and quotas of the capture are met by redrawing each
// frame's free variables, judged by the estimators `estimator` makes. Frame k draws only from the
// streams of (seed, k) and of the scene changes in effect, so any subset equals the same frames of
// a full plan.
void EvaluateCapture(const Program& capture,
                     const Program& scene,
                     uint64_t seed,
                     int64_t begin,
                     int64_t end,
                     Plan* plan,
                     const FrameEstimatorFactory& estimator = {});

// The capture used when no LCAP file is given: one nadir frame, 1024x1024
// pixels, 60 degrees horizontal field of view, over the centre of the terrain
// (or of the objects), high enough to see the whole terrain (or all objects, at
// least 10 m across).
void DefaultCapture(int64_t begin, int64_t end, Plan* plan);

}  // namespace lsds
