#include "evaluate/obb_truth.h"

#include <algorithm>
#include <map>
#include <utility>

#include "converters/dota/dota_converter.h"
#include "libs/util/error.h"

namespace lsds::evaluate {

namespace fs = std::filesystem;

namespace {

// One label line the DOTA converter writes, with the object it is of.
struct ObbRecord {
  std::string image;  // the label file's stem
  uint32_t instance_id = 0;
  DotaObject object;
};

struct ObbPiece : convert::FramePiece {
  std::vector<ObbRecord> records;
};

// A converter that writes nothing and keeps, in frame order, what the DOTA
// converter writes of each kept object (DotaLabelOf), the object's id beside
// it; run in the pass that writes the COCO truth, it sees the same objects.
class ObbCollector : public convert::Converter {
 public:
  ObbCollector(std::vector<ObbRecord>* records,
               std::vector<std::string>* images,
               std::vector<std::string>* class_names)
      : records_(records), images_(images), class_names_(class_names) {}
  std::string name() const override { return "dota (lsds evaluate)"; }
  bool NeedsMasks() const override { return false; }
  bool NeedsOrientedBoxes() const override { return true; }
  void Begin(const convert::ConvertSetup& setup) override {
    options_ = setup.options;
    for (const convert::OutputClass& c : setup.classes->classes())
      class_names_->push_back(convert::DotaClassName(c.name));
  }
  std::unique_ptr<convert::FramePiece> EncodeFrame(const convert::FrameContext& frame,
                                                   convert::LossReport*) const override {
    auto piece = std::make_unique<ObbPiece>();
    for (const convert::KeptObject& object : frame.objects) {
      const std::optional<convert::DotaLabel> label = convert::DotaLabelOf(object, *options_);
      if (!label) continue;
      ObbRecord r;
      r.image = frame.stem;
      r.instance_id = object.truth->instance_id;
      r.object.image = frame.stem;
      r.object.class_name = (*class_names_)[object.class_index];
      for (size_t k = 0; k < label->corners.size(); ++k) {
        r.object.quad[2 * k] = label->corners[k].x();
        r.object.quad[2 * k + 1] = label->corners[k].y();
      }
      r.object.difficult = label->difficult;
      piece->records.push_back(std::move(r));
    }
    return piece;
  }
  void AddFrame(const convert::FrameContext& frame,
                std::unique_ptr<convert::FramePiece> piece) override {
    images_->push_back(frame.stem);
    for (ObbRecord& r : static_cast<ObbPiece*>(piece.get())->records)
      records_->push_back(std::move(r));
  }
  void Finish() override {}

 private:
  const convert::ConvertOptions* options_ = nullptr;
  std::vector<ObbRecord>* records_;
  std::vector<std::string>* images_;
  std::vector<std::string>* class_names_;
};

std::map<std::string, int64_t> ImageIdsByStem(const EvaluationTruth& truth) {
  std::map<std::string, int64_t> ids;
  for (const ImageEntry& image : truth.images.images())
    ids[fs::path(truth.images.FileName(image)).stem().string()] = image.id;
  return ids;
}

}  // namespace

ObbTruth ReadObbTruth(const TruthOptions& options) {
  std::vector<ObbRecord> records;
  std::vector<std::string> images;
  ObbTruth out;
  std::vector<std::unique_ptr<convert::Converter>> also;
  also.push_back(std::make_unique<ObbCollector>(&records, &images, &out.dota.class_names));
  TruthOptions coco_options = options;
  coco_options.masks = false;
  EvaluationTruth truth = StreamCollectionTruth(coco_options, std::move(also));
  HoldAnnotations(&truth);

  // The devkit lists images and reads objects by label file (sorted paths).
  std::stable_sort(records.begin(), records.end(), [](const ObbRecord& a, const ObbRecord& b) {
    return a.image < b.image;
  });
  out.dota.images.insert(images.begin(), images.end());
  for (const ObbRecord& r : records) out.dota.objects.push_back(r.object);

  // Each oriented box takes the facts of its object's COCO annotation.
  const std::map<std::string, int64_t> image_ids = ImageIdsByStem(truth);
  std::map<std::pair<int64_t, uint32_t>, size_t> annotation_of;  // (image, instance) -> index
  for (size_t i = 0; i < truth.coco.ground_truth.size(); ++i)
    annotation_of[{truth.coco.ground_truth[i].image_id, truth.objects[i].instance_id}] = i;
  CocoData quads = DotaAsCoco(out.dota.class_names, out.dota.objects, {}, image_ids);
  std::vector<ObjectFacts> facts;
  facts.reserve(records.size());
  for (size_t i = 0; i < records.size(); ++i) {
    const auto it = annotation_of.find({quads.ground_truth[i].image_id, records[i].instance_id});
    if (it == annotation_of.end())
      throw Error("internal: the oriented box of instance " +
                      std::to_string(records[i].instance_id) + " in image " + records[i].image +
                      " has no COCO annotation",
                  Location(options.collection.string()));
    facts.push_back(truth.objects[it->second]);
  }
  truth.coco.ground_truth = std::move(quads.ground_truth);
  truth.coco.iou_type = IouType::kQuad;
  truth.objects = std::move(facts);
  out.truth = std::move(truth);
  return out;
}

std::vector<DetectionBox> ObbDetections(const ObbTruth& obb,
                                        const std::vector<DotaDetection>& detections) {
  return DotaAsCoco(obb.dota.class_names, {}, detections, ImageIdsByStem(obb.truth)).detections;
}

}  // namespace lsds::evaluate
