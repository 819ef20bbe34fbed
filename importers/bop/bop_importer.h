// BlenderProc's BOP writer (docs/import.md, "BlenderProc BOP"): one scene
// folder of a BOP split (e.g. bop_data/DATASET/train_pbr/000000) with
// scene_camera.json (cam_K with the pixel-centre principal point, cam_R_w2c,
// cam_t_w2c in mm, depth_scale), scene_gt.json (model-to-camera poses in mm,
// obj_id), rgb/ PNGs, depth/ 16-bit PNGs (mm / depth_scale) and mask_visib/
// PNGs, plus the dataset's models/models_info.json (model bounding boxes in
// mm). Converted to metres at import; Blender's world (z up) is declared ENU.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "importers/importer.h"
#include "libs/util/confined_path.h"

namespace lsds::import {

class BopImporter : public Importer {
 public:
  std::string name() const override { return "bop"; }
  SourceDescription Open(const std::filesystem::path& source,
                         const ImportOptions& options) override;
  SourceFrame ReadFrame(int64_t index) override;

 private:
  struct ModelBox {
    Eigen::Vector3d min_mm = Eigen::Vector3d::Zero();
    Eigen::Vector3d size_mm = Eigen::Vector3d::Zero();
  };
  std::optional<ConfinedFolder> root_;  // the scene folder: every file read is confined to it
  std::filesystem::path scene_;
  void ReadVisibFract(const std::string& key, const std::string& where, SourceFrame* frame) const;

  std::string camera_file_, gt_file_, gt_info_file_;
  nlohmann::json cameras_, gts_;
  std::optional<nlohmann::json> gt_info_;  // scene_gt_info.json when written
  // (image id, its key in scene_camera.json), in numeric order.
  std::vector<std::pair<int64_t, std::string>> image_ids_;
  std::map<uint32_t, ModelBox> models_;
  std::vector<ClassInfo> classes_;
  int width_ = 0, height_ = 0;
};

}  // namespace lsds::import
