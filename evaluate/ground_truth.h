// The ground truth `lsds evaluate` compares predictions with: the
// collection's truth exactly as `lsds convert --to coco` writes it (the COCO
// converter itself runs, into a scratch folder, so image ids, category ids,
// boxes, areas and iscrowd have one home), and the conditions each object and
// frame was seen under (docs/evaluate.md, "Conditions").
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evaluate/coco_eval.h"
#include "evaluate/dota_eval.h"
#include "libs/util/frame_selection.h"

namespace lsds::evaluate {

// What `lsds convert` is told (its flags of the same names), so that the
// ground truth is the one a model was trained and tested on.
struct TruthOptions {
  std::filesystem::path collection;
  FrameRange frames;
  std::string classes;  // --classes; empty: every class
  bool keep_classes = false;
  double min_visibility = 0;
  int64_t min_pixels = 1;
  bool masks = false;  // read each annotation's mask too (--iou-type segm)
};

// Per ground-truth annotation (parallel to CocoData::ground_truth).
struct ObjectFacts {
  int64_t frame = 0;
  uint32_t instance_id = 0;
  std::string name;  // the LSCENE symbol and copy, "T#2"
  double visibility = 0;
  double in_frame = 0;
  double size_px = 0;                // the larger side of the COCO box
  std::optional<double> distance_m;  // camera centre to the OBB centre, metres
};

// Per frame, what the collection records (absent: not recorded).
struct FrameFacts {
  std::optional<double> gsd_m;              // metadata.json gsd_m
  std::optional<double> altitude_agl_m;     // metadata.json altitude_agl_m
  std::optional<double> off_nadir_deg;      // optical axis from straight down
  std::optional<double> sun_elevation_deg;  // scene.sun.elevation_deg
  std::optional<double> fog_visibility_m;   // scene.atmosphere.visibility_m (clear: none)
  bool atmosphere_recorded = false;         // scene.atmosphere present
  std::optional<std::string> clouds;        // scene.sky.cloud_type ("none" at density 0)
  std::optional<std::string> terrain_material;
};

struct EvaluationTruth {
  CocoData coco;                            // ground truth only (detections empty)
  std::vector<std::string> category_names;  // parallel to coco.category_ids
  std::map<std::string, int64_t> image_by_file_name;
  std::map<int64_t, int64_t> frame_of_image;  // COCO image id -> frame index
  struct ImageSize {
    int64_t height = 0, width = 0;
  };
  std::map<int64_t, ImageSize> image_size;  // COCO image id -> its size
  std::vector<ObjectFacts> objects;         // parallel to coco.ground_truth
  std::map<int64_t, FrameFacts> frames;     // by frame index
  std::string capture_source;               // provenance.capture_source (LCAP text)
};

// Throws lsds::Error (exit 2) for an unreadable collection or bad options.
EvaluationTruth ReadCollectionTruth(const TruthOptions& options);

// The oriented boxes `lsds convert --to dota` writes (with the flags of
// `options`; the converter runs into a scratch folder), as the DOTA devkit
// reads them.
struct DotaTruth {
  std::vector<std::string> class_names;  // dota_classes.txt, in order
  std::set<std::string> images;          // label file stems
  std::vector<DotaObject> objects;
};
DotaTruth ReadDotaTruth(const TruthOptions& options);

// The sequences `lsds convert --to mot` writes: per sequence name, the frame
// index of each frame number (frames.txt; number k at position k - 1).
using MotSequences = std::map<std::string, std::vector<int64_t>>;
MotSequences ReadMotSequences(const TruthOptions& options);

// The COCO dataset JSON `lsds convert --to coco` writes (one split), read
// into `truth` (images, categories, annotations and their `lsds` extras;
// with `masks`, each annotation's segmentation as RLE and the iouType segm).
void ReadCocoGroundTruth(const nlohmann::json& coco,
                         const std::string& file,
                         EvaluationTruth* truth,
                         bool masks = false);

}  // namespace lsds::evaluate
