// `lsds export-scene`: each planned frame's scene as files other renderers
// read (docs/export.md): the world's triangles exactly as the reference
// renderer casts them (generator/scene/world_meshes.h) in binary glTF 2.0, and
// a JSON description per frame of what glTF cannot say: the pinhole camera
// with its principal point, the sun and sky in photometric units, the
// exposure, and each node's class, instance and render pass index.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "generator/plan/plan.h"
#include "generator/render/embree_scene.h"
#include "generator/scene_export/texture_export.h"
#include "libs/util/frame_selection.h"

namespace lsds::gen {

// What one exported node is, for renderers' object-index passes: Blender's
// pass index runs to 32767, so nodes are numbered, not given their instance
// ids; background surfaces (the skirt and the plane past it) are 0 like the sky.
struct ExportedNode {
  std::string name;
  int pass_index = 0;
  uint32_t instance_id = 0;
  uint32_t class_id = 0;
};

// The pass index of the terrain and of plan object i (the ground beyond is 0).
constexpr int kTerrainPassIndex = 1;
inline int ObjectPassIndex(size_t object) { return 2 + static_cast<int>(object); }
// The largest pass index Blender stores (Object.pass_index).
constexpr int kMaxPassIndex = 32767;

// Writes the scenes of a plan's frames into one folder: scene.json (the
// index), ground.glb (terrain, skirt and the ground plane past it, the same
// in every frame), and per frame NNNNNN.glb (its rendered objects),
// NNNNNN.json (docs/export.md) and, for each distinct sky, its images
// (NNNNNN_sky.exr, NNNNNN_clouds.exr; sky_export.h).
class SceneExporter {
 public:
  SceneExporter(const Plan& plan, const SceneAssets& assets, std::filesystem::path folder);
  // ground.glb (nothing without a terrain).
  void WriteGround() const;
  // The frame's files; returns its description (the NNNNNN.json content).
  nlohmann::json WriteFrame(const PlannedFrame& frame) const;
  // scene.json listing `frames` (plan frame indices).
  void WriteIndex(const std::vector<int64_t>& frames) const;
  // The nodes frame `frame`'s description lists, with their ids.
  static std::vector<ExportedNode> Nodes(const nlohmann::json& frame_description);

 private:
  // The sky's and clouds' images of the frame's environment (written once per
  // distinct sky) and its light records: sun, sky, atmosphere, clouds.
  nlohmann::json WriteSkyFiles(const PlannedFrame& frame,
                               const PlannedEnvironment& environment) const;

  const Plan& plan_;
  const SceneAssets& assets_;
  std::filesystem::path folder_;
  Eigen::Vector3d ground_min_, ground_max_;                  // what cloud shadows fall on
  mutable std::map<std::string, nlohmann::json> sky_files_;  // light record -> its files
  mutable TextureExporter textures_;                         // loaded assets' maps, written once
};

struct SceneExportOptions {
  std::filesystem::path output;
  FrameRange frames;
  bool force = false;
};

// Every planned frame in `options.frames`; returns how many were written.
// Refuses an existing output without `force`; the folder appears whole (it is
// written beside and renamed).
int64_t ExportScenes(const Plan& plan, const SceneExportOptions& options);

}  // namespace lsds::gen
