// `lsds export-layers`: a collection's flat layers as NumPy arrays, 16-bit PNGs
// or float TIFFs, with a layers.json that says how to read every value back
// (docs/export-layers.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "libs/util/frame_selection.h"

namespace lsds::layer_export {

enum class Target { kNpy, kPng16, kTiff };
Target ParseTarget(const std::string& name);  // npy | png16 | tiff
const char* TargetName(Target target);

// The name of the sidecar written into the output folder.
inline constexpr const char* kSidecarFile = "layers.json";

struct ExportOptions {
  std::filesystem::path collection;
  std::filesystem::path output;  // a folder; never inside the collection
  Target target = Target::kNpy;
  // Layer names (folders of the layer table). Empty: every flat layer the
  // target can hold (png16 leaves out worldposition, rgb and derived layers).
  std::vector<std::string> layers;
  FrameRange frames;
  double depth_step = 0.001;  // png16: depth quantum in world length units
  // png16: clamp depth beyond 65535 steps to the last one; otherwise such a depth is an error
  // naming the frame, the pixel and a step that holds it (a clamped depth is a wrong depth).
  bool clamp_depth = false;
  bool force = false;  // replace an existing output folder
};

struct LayerSummary {
  std::string name;
  int64_t frames = 0;          // frames written (a non-required layer may lack some)
  int64_t invalid_pixels = 0;  // non-finite values given the invalid code
  int64_t clamped_pixels = 0;  // png16: values outside the encodable range
};

struct ExportSummary {
  int64_t frames = 0;
  int64_t files = 0;
  int64_t bytes = 0;  // written
  std::vector<LayerSummary> layers;
};

// Throws lsds::Error for bad usage (unknown or deep layer, a layer the target
// cannot hold, output overlapping the collection, existing output without
// force) and bad data (an id above 65535 for png16, named by frame and pixel).
// The output folder appears only when everything has been written.
ExportSummary ExportLayers(const ExportOptions& options);

}  // namespace lsds::layer_export
