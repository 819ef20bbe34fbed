// The ground truth `lsds evaluate` compares predictions with: the
// collection's truth exactly as `lsds convert --to coco` writes it (the COCO
// converter itself runs, into a scratch folder, so image ids, category ids,
// boxes, areas and iscrowd have one home), and the conditions each object and
// frame was seen under (docs/evaluate.md, "Conditions").
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evaluate/coco_eval.h"
#include "evaluate/dota_eval.h"
#include "evaluate/truth_tables.h"
#include "libs/util/frame_selection.h"

namespace lsds::convert {
class Converter;
}  // namespace lsds::convert

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
  bool masks = false;                 // read each annotation's mask too (--iou-type segm)
  std::string mot_classes = "order";  // --mot-classes: the class ids of MOT tracker rows
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

// One image of the ground truth as the evaluation is handed it.
struct TruthImage {
  int64_t image_id = 0;
  std::vector<GroundTruthBox> boxes;  // in file order
  std::vector<ObjectFacts> objects;   // parallel to boxes
};

// The COCO dataset file the annotations are streamed from, image by image,
// when they are not held in memory (and the scratch folder holding it).
struct StreamedAnnotations;

struct EvaluationTruth {
  // Ground truth only (detections empty). Its ground_truth is empty when the
  // annotations are streamed (`streamed`); image and category ids are sorted.
  CocoData coco;
  std::vector<std::string> category_names;  // parallel to coco.category_ids
  // Per image: its frame, size and file name (sorted by id).
  ImageTable images;
  struct ImageSize {
    int64_t height = 0, width = 0;
  };
  ImageSize SizeOf(int64_t image_id) const {  // throws std::out_of_range for an unknown id
    const ImageEntry& image = images.At(image_id);
    return {image.height, image.width};
  }
  std::vector<ObjectFacts> objects;  // parallel to coco.ground_truth
  FrameTable frames;                 // by frame index
  std::string capture_source;        // provenance.capture_source (LCAP text)
  // The LCAP quotas the collection was generated under, in provenance form
  // (provenance.requirements.quotas, docs/format.md "Requirements"); each is
  // a frame condition (evaluate/conditions.h).
  nlohmann::json quotas = nlohmann::json::array();
  double metres_per_unit = 1;  // of the world frame, for distances
  // Categories whose objects are ignored, as COCO ignores a box outside the
  // area range (MOT's distractor classes, mot_results.h).
  std::set<int64_t> ignored_categories;
  std::shared_ptr<const StreamedAnnotations> streamed;
  int64_t streamed_annotations = 0;  // how many the streamed file holds

  int64_t AnnotationCount() const {
    return streamed ? streamed_annotations : static_cast<int64_t>(coco.ground_truth.size());
  }
  // Hands every image, in id order, its ground truth: from memory, or read
  // again from the streamed file (only one image's boxes held at a time).
  // Images without annotations come with none.
  void ForEachImage(const std::function<void(TruthImage&&)>& on_image) const;
};

// Throws lsds::Error (exit 2) for an unreadable collection or bad options.
// Every annotation is held in memory (coco.ground_truth, objects).
EvaluationTruth ReadCollectionTruth(const TruthOptions& options);

// The same with the annotations left in the converter's scratch file and
// streamed by ForEachImage: memory holds the image and category tables only.
EvaluationTruth StreamCollectionTruth(const TruthOptions& options);
// The same with `also` run in the converter's pass (they see the objects the
// COCO converter writes).
EvaluationTruth StreamCollectionTruth(const TruthOptions& options,
                                      std::vector<std::unique_ptr<convert::Converter>> also);

// The tables of a COCO dataset file written by `lsds convert --to coco` (one
// split), its annotations streamed from it by ForEachImage. `keep_alive`
// owns what must outlive the truth (the scratch folder holding the file).
EvaluationTruth StreamCocoGroundTruth(const std::filesystem::path& file,
                                      bool masks,
                                      std::shared_ptr<void> keep_alive = nullptr);

// Every streamed annotation into coco.ground_truth and objects.
void HoldAnnotations(EvaluationTruth* truth);

// The oriented boxes `lsds convert --to dota` writes (with the flags of
// `options`), as the DOTA devkit reads them (ReadObbTruth, obb_truth.h).
struct DotaTruth {
  std::vector<std::string> class_names;  // dota_classes.txt, in order
  std::set<std::string> images;          // label file stems
  std::vector<DotaObject> objects;
};

// The sequences `lsds convert --to mot` writes: per sequence name, the frame
// index of each frame number (frames.txt; number k at position k - 1).
using MotSequences = std::map<std::string, std::vector<int64_t>>;
MotSequences ReadMotSequences(const TruthOptions& options);

}  // namespace lsds::evaluate
