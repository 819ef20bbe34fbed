// Omniverse Replicator's BasicWriter output (docs/import.md, "Omniverse
// Replicator"): per frame NNNN, rgb_NNNN.png, distance_to_image_plane_NNNN.npy
// or distance_to_camera_NNNN.npy (float32, scene units),
// instance_segmentation_NNNN.png (colourised RGBA) with
// instance_segmentation_mapping_NNNN.json (colour -> prim path) and
// instance_segmentation_semantics_mapping_NNNN.json (colour -> {"class": ..}),
// bounding_box_3d_NNNN.npy (structured records, local extents and a
// row-vector local-to-world transform) with its _labels and _prim_paths JSON,
// bounding_box_2d_tight_NNNN.npy (inclusive pixel indices, occlusionRatio) and
// camera_params_NNNN.json (row-vector view and OpenGL projection matrices,
// metersPerSceneUnit). The layouts BasicWriter.write() makes: one render
// product's files in one folder, or several products' in
// <product>/<annotator>/ folders, or with use_common_output_dir in
// <annotator>/<product>_ names (each product one sequence); on_time
// triggers prefix the frame number with their counts (rgb_1_0000.png). The
// objects are the prims with a 3D box and those with only a tight 2D box (no
// obb); without instance segmentation their 2D truth comes from
// bounding_box_2d_tight. The stage's up axis is not in the files: it
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
  // One render product's output.
  struct Product {
    std::string name;
    std::filesystem::path folder;
    bool annotator_folders = false;  // files in <folder>/<annotator>/
    std::string file_prefix;         // "<product>_" before each file name (common output dir)
  };
  // One frame: its product and the name part after "<stem>_" ("0000", "1_0000").
  struct FrameFiles {
    size_t product = 0;
    std::string trigger_prefix;  // on_time trigger counts, "1_" ("" without)
    std::vector<int64_t> order;  // trigger counts then frame number, for sorting
    std::string id;
  };
  // The file `stem`_<id>.`ext` of frame `index`, written by `annotator`.
  std::filesystem::path Path(const std::string& annotator,
                             const std::string& stem,
                             int64_t index,
                             const std::string& ext) const;
  void FindFrames(const Product& product, size_t product_index);
  // The stages of Open: the products, their frames, the layers the first frame has, the prims
  // and classes of every frame numbered, then the description.
  struct PrimLabels;
  void FindProducts(const std::filesystem::path& source);
  void FindLayers();
  void ScanInstanceMappings(int64_t index, PrimLabels* labels) const;
  std::vector<std::pair<std::string, std::string>> ScanBoxes(const std::string& annotator,
                                                             int64_t index) const;
  void NumberPrims(const PrimLabels& labels, SourceDescription* description);
  void DescribeTruth(const ImportOptions& options, SourceDescription* description) const;
  void ReadTightBoxes(int64_t index, SourceFrame* frame) const;
  std::optional<ConfinedFolder> root_;  // every file read is confined to it
  std::vector<Product> products_;
  std::vector<FrameFiles> frames_;  // by product, trigger counts, frame number
  bool has_instances_ = false;      // instance_segmentation written
  std::string depth_stem_;          // distance_to_image_plane | _camera
  DepthKind depth_kind_ = DepthKind::kPlanar;
  std::map<std::string, uint32_t> instance_of_prim_;  // prim path -> id
  std::map<std::string, uint32_t> class_of_prim_;     // prim path -> class
  std::map<std::string, uint32_t> class_ids_;         // class name -> id
  Eigen::Matrix3d enu_from_stage_ = Eigen::Matrix3d::Identity();
};

}  // namespace lsds::import
