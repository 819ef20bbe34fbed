// Per-object truth of a rendered frame (docs/format.md): the 3D OBB, the tight
// visible box and pixel count from the instanceid layer, the projected OBB
// bounds, the visibility fraction (visible pixels / pixels the object covers
// when rendered alone, with the same centre samples) and the in-frame fraction.
#pragma once

#include <cstdint>
#include <vector>

#include "generator/plan/plan.h"
#include "generator/render/embree_scene.h"
#include "generator/render/film.h"
#include "libs/collection/model.h"

namespace lsds::gen {

// Objects of interest (target, rendered, with class and instance ids) whose
// projected box meets the image or that have visible pixels, in plan order.
// The transmittance is that of the atmosphere (extinction per metre) from the
// camera centre to the OBB centre. Adds the rays it casts to `rays`.
struct TruthOptions {
  // Count the pixels where the object is visible as unoccluded without casting
  // their rays again (exact, see truth.cc); off casts every ray of the
  // object's bounds, the reference the tests compare against.
  bool reuse_visible_pixels = true;
};
std::vector<ObjectTruth> ComputeObjectTruth(const RenderScene& scene,
                                            const PlannedFrame& frame,
                                            const Film& film,
                                            double extinction_per_m,
                                            uint64_t* rays,
                                            const TruthOptions& options = {});

}  // namespace lsds::gen
