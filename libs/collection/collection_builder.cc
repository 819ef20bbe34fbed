#include "libs/collection/collection_builder.h"

#include <tbb/parallel_for.h>

#include "libs/collection/json_io.h"
#include "libs/collection/motion_layout.h"
#include "libs/collection/rig.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds {

namespace fs = std::filesystem;

std::map<std::string, std::string> WriteFrameLayers(const fs::path& root,
                                                    const CollectionHeader& header,
                                                    int64_t frame_index,
                                                    const CameraTruth& camera,
                                                    const FrameImages& images,
                                                    const std::optional<std::string>& rig_camera) {
  std::map<std::string, std::string> files;
  for (const LayerInfo& layer : header.layers) {
    if (layer.deep && images.bundle == nullptr)
      throw Error("frame " + std::to_string(frame_index) + ": layer '" + layer.name +
                  "' is deep but no bundle was rendered");
    if (!layer.deep && (images.flat == nullptr || images.flat->count(layer.semantic) == 0))
      throw Error("frame " + std::to_string(frame_index) + ": no image for layer '" + layer.name +
                  "'");
    files[layer.name] = layer.name + "/" + FrameFileStem(frame_index, rig_camera) + ".exr";
  }
  // Residual worldposition and motion layers predict from the depth as stored
  // and the camera as collection.json holds it (nlohmann writes doubles in
  // their shortest round-trip form, so every reader parses these very bits).
  std::optional<WorldPositionPrediction> prediction;
  std::string depth_layer;
  for (const LayerInfo& layer : header.layers) {
    if ((layer.semantic != "worldposition" && layer.semantic != "motion") ||
        layer.flat_layout != FlatLayout::kResidual)
      continue;
    const LayerInfo* depth = header.FindLayerBySemantic("depth");
    if (depth == nullptr || depth->deep || images.flat->count("depth") == 0) {
      throw Error("frame " + std::to_string(frame_index) + ": layer '" + layer.name +
                  "' is residual but the collection has no flat depth layer to predict from");
    }
    if (layer.semantic == "motion" && !images.motion_reference) {
      throw Error("frame " + std::to_string(frame_index) + ": layer '" + layer.name +
                  "' is residual but the frame's previous camera is not known");
    }
    if (!prediction) prediction = PredictionFromDepth(images.flat->at("depth"), *depth, camera);
    depth_layer = depth->name;
  }
  // Layers are independent files: encode them in parallel.
  tbb::parallel_for(size_t{0}, header.layers.size(), [&](size_t i) {
    const LayerInfo& layer = header.layers[i];
    exr::WriteOptions write;
    write.compression = layer.compression;
    write.camera = HeaderCameraOf(camera);
    const fs::path path = root / files.at(layer.name);
    if (layer.deep) {
      // A residual bundle predicts depths with the frame's camera.
      std::optional<BundleSampling> sampling = images.bundle_sampling;
      if (sampling) {
        sampling->view = BundleView{camera.intrinsics,
                                    camera.cam_from_world_rotation,
                                    layer.depth_kind.value_or(DepthKind::kPlanar)};
      }
      WriteBundleExr(path, *images.bundle, layer.layout, sampling, write);
    } else if (layer.semantic == "worldposition") {
      WriteWorldPositionExr(path,
                            images.flat->at(layer.semantic),
                            layer.flat_layout,
                            prediction ? &*prediction : nullptr,
                            depth_layer,
                            write);
    } else if (layer.semantic == "motion") {
      WriteMotionExr(
          path,
          images.flat->at(layer.semantic),
          layer.flat_layout,
          prediction ? &*prediction : nullptr,
          images.motion_reference ? images.motion_reference->previous_camera : std::nullopt,
          depth_layer,
          write);
    } else {
      exr::WriteFlatExr(path, images.flat->at(layer.semantic), write);
    }
  });
  return files;
}

namespace {
MetadataHeader TruthMetadataHeader(const CollectionHeader& header) {
  MetadataHeader metadata;
  metadata.frame_count = header.frame_count;
  return metadata;
}
}  // namespace

CollectionBuilder::CollectionBuilder(const fs::path& root, const CollectionHeader& header)
    : header_(header),
      collection_(root, header),
      metadata_(root / kMetadataFile, TruthMetadataHeader(header)) {}

void CollectionBuilder::Append(const Frame& truth) {
  Append(truth, TruthMetadata(truth, header_.conventions.world));
}

void CollectionBuilder::Append(const Frame& truth, const MetadataFrame& metadata) {
  collection_.Append(truth);
  metadata_.Append(metadata);
}

void CollectionBuilder::Commit() {
  metadata_.Commit();
  collection_.Commit();
}

}  // namespace lsds
