// Unreal Engine 5 Movie Render Queue: one multilayer (single-part) or
// multipart EXR per frame with the final image, the World Depth pass (planar,
// cm, float or half) and a Cryptomatte actor layer (ids + manifest in the
// header), the camera in `unreal/camera/...` header attributes, and a sidecar
// `lsds_objects.json` (written by the UE Python script of docs/import.md) that
// names the actors' classes, instance ids and 3D boxes. Converted to ENU
// metres at import (docs/import.md, "UE5 Movie Render Queue").
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "importers/importer.h"
#include "importers/source_exr.h"
#include "libs/util/confined_path.h"

namespace lsds::import {

inline constexpr const char* kUeObjectsFile = "lsds_objects.json";

class UeMrqImporter : public Importer {
 public:
  std::string name() const override { return "ue-mrq"; }
  SourceDescription Open(const std::filesystem::path& source,
                         const ImportOptions& options) override;
  SourceFrame ReadFrame(int64_t index) override;

 private:
  struct Actor {
    uint32_t instance_id = 0;
    uint32_t class_id = 0;
  };
  struct FrameFile {
    std::filesystem::path path;
    std::string sequence;
    int64_t number = 0;
  };
  void ReadObjects(const std::filesystem::path& file);
  // The channels of the final image, depth and Cryptomatte, from the first frame.
  void ReadLayout(const SourceExr& first);
  SourceDescription Describe() const;
  void ReadDepth(const SourceExr& exr, SourceFrame* frame) const;
  void ReadIds(const SourceExr& exr, int64_t index, SourceFrame* frame) const;

  std::optional<ConfinedFolder> root_;  // every file read is confined to it
  std::vector<FrameFile> files_;
  std::map<std::string, Actor> actors_;  // by Cryptomatte manifest name
  std::vector<ObjectIdentity> targets_;
  std::vector<ClassInfo> classes_;
  double fps_ = 24;
  double sky_depth_cm_ = 1e7;
  std::string rgb_prefix_;
  std::string depth_channel_;  // empty: no World Depth pass
  std::string id_layer_;       // empty: no Cryptomatte actor layer
  std::string id_channel_, coverage_channel_;
  bool fov_of_display_window_ = false;
  std::vector<std::string> warnings_;
  int width_ = 0, height_ = 0;
  int64_t shot_ = 0;
};

}  // namespace lsds::import
