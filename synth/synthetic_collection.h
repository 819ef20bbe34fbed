// Synthetic collections with exact, analytic layers and truth, written through
// the real writers, so that every tool can be tested without the renderer.
// Layers follow docs/format.md exactly.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>
#include "libs/collection/bundle_layout.h"

#include "libs/collection/model.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/flat_image.h"
#include "synth/analytic_scene.h"

namespace lsds::synth {

struct Spec {
  int width = 64;
  int height = 48;
  double hfov_deg = 60;
  std::vector<ClassInfo> classes;       // 1 "ground", 2 "box", 3 "crate" by default
  bool ground = true;                   // plane z = 0, class 1, instance 1000 (not a target)
  std::vector<Box> boxes;               // the targets
  std::vector<Rigid3d> cam_from_world;  // one per frame
  double frame_interval = 0.1;          // seconds
  std::string sequence = "S1";
  int samples_per_axis = 2;  // bundle: n*n stratified samples, one moved to the pixel centre
  DepthKind depth_kind = DepthKind::kPlanar;
  // Storage of the bundle layer (docs/format.md "Pixel bundles"). compact
  // derives the positions only at 1 sample per pixel (the pattern here is not
  // the generator's rule beyond that) and stores them otherwise.
  BundleLayout bundle_layout = BundleLayout::kFull;
  std::vector<std::string> layers;  // semantics to write; empty = every standard layer
  Eigen::Vector3d direction_to_sun = Eigen::Vector3d(0.3, 0.2, 1.0).normalized();

  AnalyticScene Scene() const;
  std::vector<std::string> LayerSemantics() const;
};

// Ground + 3 boxes, 4 frames: a nadir camera at 20 m moving +x by 1 m per
// frame.
Spec DefaultSpec();

// DefaultSpec with `frames` nadir frames on a 3 m circle around the boxes at 20
// m, at any size: a stand-in collection of any length for demos and benchmarks.
Spec CircleSpec(int frames, int width, int height);

// A nadir camera (looking straight down, image x east, image top north) at
// `position_in_world`.
Rigid3d NadirCamFromWorld(const Eigen::Vector3d& position_in_world);

struct RenderedFrame {
  std::map<std::string, exr::FlatImage> flat;  // by semantic
  exr::DeepImage bundle;
  Frame truth;  // files left empty
};

// Renders frame `frame` of `spec`: single-value layers at the pixel centre, RGB
// averaged over the bundle's samples, truth measured on the rendered instance
// layer.
RenderedFrame RenderFrame(const Spec& spec, int frame);

// Writes a complete collection (layers, collection.json, metadata.json) into
// `root`, which must not exist or be empty.
void WriteCollection(const std::filesystem::path& root, const Spec& spec);

}  // namespace lsds::synth
