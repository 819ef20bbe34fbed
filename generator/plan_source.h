// Where every command gets a plan: LSCENE/LCAP through the planner
// (generator/lang), a plan JSON file, or the built-in demo; restricted to the
// frames of --frames, checked against the plan's frames.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "generator/demo_plan.h"
#include "generator/plan/plan.h"
#include "libs/util/frame_selection.h"

namespace lsds::gen {

// The plan of SCENE (and CAPTURE, may be empty) for `seed`, restricted to the
// frames `frames` selects (default: every frame). Frames are planned
// independently (frame k depends on (seed, k) only), so the restricted plan
// holds the same frames as the full one. A selection that reaches outside the
// plan is an lsds::Error naming the plan's frames (exit 2).
Plan PlanFromScene(const std::string& scene,
                   const std::string& capture,
                   uint64_t seed,
                   const FrameSelection& frames = {});

// Throws lsds::Error naming the plan's frame range when `frames` reaches
// outside the frames of `plan`.
void CheckPlanFrames(const FrameSelection& frames, const Plan& plan);

// Reads a plan JSON file (schemas/plan.schema.json).
Plan LoadPlanJson(const std::string& path);

// What `lsds generate` renders: exactly one of a scene (with its capture), a
// plan file, or the demo.
struct PlanRequest {
  std::string scene;
  std::string capture;
  std::string plan_file;
  std::optional<DemoOptions> demo;
  std::optional<uint64_t> seed;  // default 0; a plan file's own seed unless given
  FrameSelection frames;         // checked against the plan's frames
};

// The plan to render `request.frames` of: for a scene, also the frames the
// first selected frame's motion is measured against (one time step back; in a
// rig the previous step's frame of every camera), which are planned but not
// rendered (GenerateOptions::frames selects), so that --frames gives the
// bytes of the single run. Throws lsds::Error for no source or several, and
// for a selection outside the plan, before any output is touched.
Plan PlanForRendering(const PlanRequest& request);

}  // namespace lsds::gen
