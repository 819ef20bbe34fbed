// GenerateCollection: renders the frames of a plan into a complete flat
// collection (docs/format.md, docs/generator.md): one EXR per standard layer
// per frame, collection.json with per-frame camera and per-object truth,
// metadata.json equal to truth.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "generator/cycles/cycles_frame.h"
#include "generator/plan/plan.h"
#include "generator/render/film.h"
#include "generator/requirement_report.h"
#include "libs/collection/layer_layouts.h"
#include "libs/collection/model.h"
#include "libs/util/frame_selection.h"

namespace lsds::gen {

// What makes the rgb layer (docs/generator.md, "Blender Cycles"): lsds's reference renderer, or
// Blender Cycles rendering the exported scene (lsds export-scene) while every truth layer still
// comes from lsds's own ray casts.
enum class Renderer { kReference, kCycles };

struct GenerateOptions {
  std::filesystem::path output;
  int spp = 4;          // samples per pixel, a square (stratified n x n)
  double jitter = 1.0;  // share of the stratum each sample may move within
  int threads = 0;      // 0: all cores
  bool force = false;   // replace an existing output
  bool resume = false;  // keep the complete frames of an interrupted run
  bool progress = true;
  // Frames with index in `frames`, and index % shard_count == shard_index.
  FrameRange frames;
  int shard_index = 0;
  int shard_count = 1;
  DepthKind depth_kind = DepthKind::kPlanar;
  // zlib level of the ZIP/ZIPS layers (OpenEXR's process-wide default; 1
  // encodes about twice as fast as OpenEXR's own default 4 for files a few
  // percent larger).
  int zip_level = 1;
  // How the deep bundle, worldposition and motion layers are stored (`--compact`,
  // `--*-layout`): libs/collection/layer_layouts.h.
  LayerLayouts layouts;
  Renderer renderer = Renderer::kReference;
  // --renderer cycles: Blender's executable (empty: `blender` on PATH), its
  // version (found by GenerateCollection), and OpenImageDenoise on the rgb.
  std::string blender;
  std::string blender_version;
  bool denoise = false;

  void Check() const;  // throws lsds::Error for inconsistent options
  bool Selects(int64_t frame_index) const {
    return frames.Contains(frame_index) && frame_index % shard_count == shard_index;
  }
};

struct GenerateSummary {
  RequirementSummary requirements;
  int64_t frames_rendered = 0;
  int64_t frames_skipped = 0;  // complete frames kept by --resume
  uint64_t rays = 0;           // primary, shadow and visibility rays
  double render_seconds = 0;   // scene builds, ray casting, shading and truth
  double write_seconds = 0;    // EXR encoding and JSON
  double total_seconds = 0;
  // A frame's cost once the pipeline is full (with 2 or more frames
  // rendered): frame k renders while frame k - 1 is written, so from the end
  // of the first render to the end of the last frame's render and the write
  // before it, N - 1 frames were rendered and N - 1 written. Leaves out the
  // first render, which nothing overlaps, and the last write (the pipeline's
  // fill and drain), which a long collection amortizes. 0 with fewer frames.
  double steady_seconds_per_frame = 0;
  // --renderer cycles: the scene export (before any frame) and Blender's run
  // (beside lsds's render and writes), and per rendered frame how Cycles' depth
  // and object index agreed with lsds's layers.
  double export_seconds = 0;
  double cycles_seconds = 0;
  std::vector<CyclesAgreement> cycles_agreement;
};

GenerateSummary GenerateCollection(const Plan& plan, const GenerateOptions& options);

// The collection header (provenance, classes, layer table) GenerateCollection
// writes.
CollectionHeader MakeHeader(const Plan& plan, const GenerateOptions& options);
}  // namespace lsds::gen
