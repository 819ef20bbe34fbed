// Omniverse Replicator's BasicWriter output for one render product
// (docs/import.md, "Omniverse Replicator"): per frame NNNN, rgb_NNNN.png,
// distance_to_image_plane_NNNN.npy or distance_to_camera_NNNN.npy (float32,
// scene units), instance_segmentation_NNNN.png (colourised RGBA) with
// instance_segmentation_mapping_NNNN.json (colour -> prim path) and
// instance_segmentation_semantics_mapping_NNNN.json (colour -> {"class": ..}),
// bounding_box_3d_NNNN.npy (structured records, local extents and a
// row-vector local-to-world transform) with its _labels and _prim_paths JSON,
// and camera_params_NNNN.json (row-vector view and OpenGL projection
// matrices, metersPerSceneUnit). The stage's up axis is not in the files: it
// comes from --up-axis.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "importers/importer.h"
#include "libs/util/confined_path.h"

namespace lsds::import {

class ReplicatorImporter : public Importer {
 public:
  std::string name() const override { return "replicator"; }
  SourceDescription Open(const std::filesystem::path& source,
                         const ImportOptions& options) override;
  SourceFrame ReadFrame(int64_t index) override;

 private:
  std::filesystem::path Path(const std::string& stem, int64_t index, const std::string& ext) const;
  std::optional<ConfinedFolder> root_;  // every file read is confined to it
  std::filesystem::path folder_;
  // (number, its digits as written: "0000", ...) in numeric order.
  std::vector<std::pair<int64_t, std::string>> frame_ids_;
  std::string depth_stem_;  // distance_to_image_plane | _camera
  DepthKind depth_kind_ = DepthKind::kPlanar;
  std::map<std::string, uint32_t> instance_of_prim_;  // prim path -> id
  std::map<std::string, uint32_t> class_of_prim_;     // prim path -> class
  std::map<std::string, uint32_t> class_ids_;         // class name -> id
  Eigen::Matrix3d enu_from_stage_ = Eigen::Matrix3d::Identity();
};

}  // namespace lsds::import
