// A UE5 Movie Render Queue output folder synthesized from an lsds analytic
// scene (no Unreal needed), in the layout docs/import.md describes: one EXR
// per frame named {sequence}.{frame:04d}.exr with the final image (R, G, B,
// A), the World Depth pass (FinalImageMovieRenderQueue_WorldDepth.R, planar
// cm), a Cryptomatte layer CryptoActor (ids + manifest) and the unreal/camera
// header attributes, plus the lsds_objects.json sidecar.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "synth/synthetic_collection.h"

namespace lsds::testing {

struct MrqFixtureOptions {
  bool multipart = true;    // else one part with layer-prefixed channels
  bool half_depth = false;  // MRQ often writes half
  std::string sequence = "Shot";
  double fps = 10;  // frame k is numbered k: time k / fps
};

// Actor names in the Cryptomatte manifest: the ground and each box.
std::string MrqActorName(uint32_t instance_id);

// Writes the fixture of `spec` into `folder`; returns the rendered frames'
// instance id layers (what the Cryptomatte rank 0 encodes).
void WriteMrqFixture(const std::filesystem::path& folder,
                     const synth::Spec& spec,
                     const MrqFixtureOptions& options = {});

}  // namespace lsds::testing
