// Kubric's scene folder (docs/import.md, "Kubric"): what a worker such as
// challenges/movi/movi_def_worker.py leaves in its job_dir through
// kb.write_image_dict and kb.write_json: metadata.json (scene resolution,
// frame rate, camera K normalised by the image size, positions, WXYZ
// quaternions of a Blender camera looking down -Z with +Y up, and the
// instances with their 8 world corners per frame, `bboxes_3d`),
// rgba_%05d.png, depth_%05d.tiff (float32 distance along the ray) and
// segmentation_%05d.png (8-bit palette PNG: 0 background, k the k-th entry of
// `instances`). Converted to the OpenCV camera and pixel-edge intrinsics.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "importers/importer.h"
#include "libs/util/confined_path.h"

namespace lsds::import {

class KubricImporter : public Importer {
 public:
  std::string name() const override { return "kubric"; }
  SourceDescription Open(const std::filesystem::path& source,
                         const ImportOptions& options) override;
  SourceFrame ReadFrame(int64_t index) override;

 private:
  struct Instance {
    uint32_t class_id = 0;
    std::string name, asset;
  };
  std::optional<ConfinedFolder> root_;  // every file read is confined to it
  std::filesystem::path scene_;
  std::string metadata_file_;
  nlohmann::json camera_;     // metadata.json "camera"
  nlohmann::json instances_;  // metadata.json "instances"
  std::vector<Instance> identities_;
  int width_ = 0, height_ = 0;
  double frame_rate_ = 1;
  Eigen::Matrix3d normalised_k_ = Eigen::Matrix3d::Identity();
};

}  // namespace lsds::import
