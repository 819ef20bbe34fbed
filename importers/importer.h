// The interface every source format implements (docs/import.md). An importer
// only decodes its source into frames in the collection's conventions (ENU
// metres, OpenCV camera, pixel-edge image coordinates); the driver
// (import_collection.h) derives what the source lacks and writes through the
// one collection builder. Frames are read one at a time, in order, so memory
// does not grow with the number of frames.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/collection/layer_layouts.h"
#include "libs/collection/model.h"
#include "libs/collection/object_truth.h"
#include "libs/exr/flat_image.h"

namespace lsds::import {

struct ImportOptions {
  // A sidecar file with the objects' identities and 3D boxes, for sources
  // that do not store them; empty: the importer's default place.
  std::filesystem::path objects;
  // The simulator's settings file where the source does not hold it (AirSim:
  // settings.json with the camera mount); empty: the importer's default.
  std::filesystem::path settings;
  // The world's up axis where the source does not say (Replicator: the USD
  // stage's upAxis, "z" or "y"); converted to ENU's z up.
  std::string up_axis = "z";
  // Which EXR window a horizontal FOV attribute spans (ue-mrq): "data" (the
  // rendered image; Movie Render Queue's rule) or "display".
  std::string fov_window = "data";
  // Whether files of the source may be symbolic links that resolve outside it
  // (--allow-links-outside): deliberately linked data. Names in the source's
  // data must be relative and inside it either way (libs/util/confined_path.h).
  bool allow_links_outside = false;
  // Whether every label the source defines becomes a class (--all-labels);
  // by default only the labels its frames use (SOLO).
  bool all_labels = false;
  // How the collection stores its layers (--compact: the residual worldposition;
  // libs/collection/layer_layouts.h); the importer does not see it.
  LayerLayouts layouts;
};

// What the whole source holds, known before the first frame is read.
struct SourceDescription {
  std::vector<ClassInfo> classes;
  int64_t frame_count = 0;
  // Flat layers every frame provides, by semantic (rgb, classid, instanceid,
  // depth, ...), with the standard channels (model.h StandardLayer).
  std::vector<std::string> semantics;
  DepthKind depth_kind = DepthKind::kPlanar;
  // Where each truth field comes from: "imported" (read from the source) or
  // "derived" (computed from its layers); the driver adds its own.
  std::map<std::string, std::string> truth_origin;
  // The source's own units and frames, recorded for people.
  nlohmann::json source_conventions = nlohmann::json::object();
  // What the user should know (an assumed default, a pass not read, what
  // the collection cannot keep); the driver adds them to
  // ImportResult::warnings, printed by `lsds import`, never fatal.
  std::vector<std::string> warnings;
};

struct SourceFrame {
  double time = 0;
  std::string sequence;
  int64_t shot = 0;
  CameraTruth camera;  // ENU metres, OpenCV camera, pixel-edge intrinsics
  // By semantic, with the standard channels; lengths in metres.
  std::map<std::string, exr::FlatImage> flat;
  // The objects of interest (OBB in ENU metres): each gets a truth entry when
  // it is near the image.
  std::vector<ObjectIdentity> targets;
  // Per-object truth the source states itself, by instance id: its
  // visibility (BOP's visib_fract, Replicator's 1 - occlusionRatio, SOLO's
  // OcclusionMetric) and in-frame share (SOLO's) replace the derived ones; its
  // 2D box (Replicator's bounding_box_2d_tight) is used for frames with no
  // instanceid layer to measure one on.
  struct StatedTruth {
    std::optional<Box2d> bbox;  // pixel-edge, visible pixels
    std::optional<double> visibility;
    std::optional<double> in_frame;
  };
  std::map<uint32_t, StatedTruth> stated;
};

class Importer {
 public:
  virtual ~Importer() = default;
  virtual std::string name() const = 0;
  // Reads the source's layout; throws lsds::Error naming file and field when
  // the source is not what it claims.
  virtual SourceDescription Open(const std::filesystem::path& source,
                                 const ImportOptions& options) = 0;
  // Frame `index` (0-based, called in increasing order).
  virtual SourceFrame ReadFrame(int64_t index) = 0;
};

}  // namespace lsds::import
