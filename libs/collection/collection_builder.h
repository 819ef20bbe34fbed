// The one path by which rendered or imported frames become a collection: layer
// files written under their standard names with the frame's camera in their
// headers, then collection.json and metadata.json (equal to truth) streamed
// frame by frame and committed atomically. The generator, synth and the
// importers write through it.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "libs/collection/collection_writer.h"
#include "libs/collection/model.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/flat_image.h"

namespace lsds {

// The images of one frame: flat layers by semantic, and the deep bundle.
struct FrameImages {
  const std::map<std::string, exr::FlatImage>* flat = nullptr;
  const exr::DeepImage* bundle = nullptr;  // required if a layer is deep
  // How the bundle was sampled: lets a compact bundle layer derive its sample
  // positions instead of storing them. Without it the full layout is written.
  std::optional<BundleSampling> bundle_sampling;
  // What a residual motion layer predicts from besides the depth: the camera
  // motion is measured against (the previous frame of the shot; none on a
  // shot's first frame). Unset: not known, and a residual motion layer is an
  // error.
  struct MotionReference {
    std::optional<CameraTruth> previous_camera;
  };
  std::optional<MotionReference> motion_reference;
};

// Writes every layer of `header` for frame `frame_index` under `root` (layer
// files in parallel, each atomically) and returns their relative paths
// (layer name -> "name/000042.exr"; "name/000042_left.exr" for a frame of rig
// camera "left", libs/collection/rig.h). A layer's image is found by its
// semantic.
std::map<std::string, std::string> WriteFrameLayers(
    const std::filesystem::path& root,
    const CollectionHeader& header,
    int64_t frame_index,
    const CameraTruth& camera,
    const FrameImages& images,
    const std::optional<std::string>& rig_camera = std::nullopt);

// collection.json and metadata.json of `header`, frame by frame, in order.
// header.frame_count frames must be appended before Commit().
class CollectionBuilder {
 public:
  CollectionBuilder(const std::filesystem::path& root, const CollectionHeader& header);
  // metadata.json gets the truth pose (TruthMetadata) ...
  void Append(const Frame& truth);
  // ... or what the caller measured, e.g. TruthMetadata plus survey fields.
  void Append(const Frame& truth, const MetadataFrame& metadata);
  void Commit();

 private:
  CollectionHeader header_;
  CollectionWriter collection_;
  MetadataWriter metadata_;
};

}  // namespace lsds
