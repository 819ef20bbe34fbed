// The integrator: renders one frame of a world state into the film of every
// standard layer. The image is cut into blocks of 2x2 pixels whose camera,
// shadow and disocclusion rays are cast together as Embree packets
// (ray_casts.h); tiles of blocks run in parallel over TBB. A pixel's values
// depend only on its own samples (and its block's packets, which are always
// the same rays), so the result is the same for any thread count or tile
// size.
#pragma once

#include <cstdint>
#include <vector>

#include "generator/plan/plan.h"
#include "generator/render/embree_scene.h"
#include "generator/render/film.h"
#include "generator/render/sampler.h"
#include "generator/render/sky.h"
#include "libs/geometry/camera.h"

namespace lsds::gen {

struct RenderSettings {
  SamplerSettings sampler;
  DepthKind depth_kind = DepthKind::kPlanar;
  int tile_size = 16;  // pixels per side of a tile (whole blocks)
  bool bundle = true;  // fill the film's pixel bundle (the deep layer)
  // Compute motion vectors (their disocclusion rays); off when the capture
  // does not write the motion layer, which then stays NaN.
  bool motion = true;
  // Trace the rays of a block of pixels as coherent Embree packets
  // (rtcIntersect16, rtcOccluded16, ...); off traces them one by one
  // (rtcIntersect1, rtcOccluded1). Same films either way, except where a ray
  // passes exactly through an edge two triangles share: then either
  // triangle may be reported (tests/generator/render_test.cc).
  bool packets = true;
  // Evaluate the procedural albedo and the cloud shadow once per pixel where
  // they are smooth over it (PixelField); off evaluates them at every sample.
  // Only the RGB can change; every truth layer is the same either way.
  bool reuse_smooth_fields = true;
  // Shade a pixel's diffuse samples once, at its centre sample, where its
  // other samples see the same triangle under the same light to within
  // kShadeOnceTolerance (docs/generator.md, "Diffuse pixels shaded once");
  // off shades every sample. Only the RGB can change; every truth layer is
  // the same either way.
  bool shade_pixels_once = true;
  // Shade the rgb layer; off (`lsds generate --renderer cycles`, whose rgb
  // comes from Blender) casts only what the truth layers need: the camera
  // rays, the disocclusion rays and one shadow ray per pixel, at its centre
  // sample, which the shadow layer takes. The rgb is then 0. Every truth
  // layer is the same either way.
  bool shade_rgb = true;
  // Show the terrain families' ground detail (generator/scene/ground_detail.h);
  // off renders them with their smooth patterns alone, which a pixel's
  // samples can share (the two settings above). Only the RGB changes.
  bool ground_detail = true;
};

// How far apart a sample's direct sunlight and fog may be from its pixel's
// centre sample's, relative, for the sample to take the centre's radiance
// (RenderSettings::shade_pixels_once): a quarter of an 8-bit step.
constexpr double kShadeOnceTolerance = 1.0 / 1024;

// The previous frame of the same shot, for motion vectors (absent on a shot's
// first frame, whose motion is all NaN). `scene` is the previous world's ray
// scene, used to find disoccluded pixels (NaN too); null skips that test.
struct PreviousView {
  const PlannedFrame* frame = nullptr;
  const WorldState* world = nullptr;
  const RenderScene* scene = nullptr;
};

Film RenderFrame(const RenderScene& scene,
                 const Sky& sky,
                 const PlannedFrame& frame,
                 const PreviousView& previous,
                 const RenderSettings& settings);

// The same, into `film`: an earlier frame's film of the same size is reused
// (Film::Reshape), so a run of frames allocates (and page-faults) its films
// once. Every value of every channel is rewritten.
void RenderFrame(const RenderScene& scene,
                 const Sky& sky,
                 const PlannedFrame& frame,
                 const PreviousView& previous,
                 const RenderSettings& settings,
                 Film* film);

}  // namespace lsds::gen
