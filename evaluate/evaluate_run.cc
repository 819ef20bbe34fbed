#include "evaluate/evaluate_run.h"

#include "evaluate/conditions.h"
#include "evaluate/dota_files.h"
#include "evaluate/mot_results.h"
#include "evaluate/obb_truth.h"
#include "evaluate/predictions.h"
#include "evaluate/strata.h"
#include "evaluate/suggest.h"
#include "evaluate/yolo_results.h"
#include "libs/collection/collection_reader.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/output_guard.h"
#include "libs/util/text_check.h"

namespace lsds::evaluate {

namespace {

EvaluationReport BaseReport(const EvaluationTruth& truth, int64_t thin_below) {
  EvaluationReport report;
  report.images = static_cast<int64_t>(truth.coco.image_ids.size());
  report.annotations = truth.AnnotationCount();
  for (size_t k = 0; k < truth.coco.category_ids.size(); ++k)
    report.categories.emplace_back(truth.coco.category_ids[k], truth.category_names[k]);
  report.thin_below = thin_below;
  return report;
}

// The predictions of the COCO path in any of the formats that hold boxes,
// into `out` in file order (a COCO results file entry by entry).
void ReadBoxPredictions(const EvaluateOptions& options,
                        const EvaluationTruth& truth,
                        DetectionsByImage* out) {
  if (options.format == "coco") {
    ReadCocoPredictions(
        options.predictions, truth, [out](DetectionBox&& d) { out->Add(std::move(d)); });
    return;
  }
  std::vector<DetectionBox> detections;
  if (options.format == "yolo") {
    detections = options.iou_type == "segm" ? ReadYoloSegmentDetections(options.predictions, truth)
                                            : ReadYoloDetections(options.predictions, truth);
  } else {
    detections = ReadMotDetections(
        options.predictions, truth, ReadMotSequences(options.truth), options.truth.mot_classes);
  }
  for (DetectionBox& d : detections) out->Add(std::move(d));
}

}  // namespace

void EvaluateOptions::Check() const {
  if (format != "coco" && format != "dota" && format != "yolo" && format != "mot")
    throw Error("--format " + format + ": expected coco, dota, yolo or mot");
  if (format == "mot" && iou_type != "bbox")
    throw Error("MOT tracker files hold boxes: --iou-type bbox with --format mot");
  if (iou_type != "bbox" && iou_type != "segm" && iou_type != "obb")
    throw Error("--iou-type " + iou_type + ": expected bbox, segm or obb");
  if (format == "dota" && iou_type != "obb")
    throw Error("DOTA task-1 files hold oriented boxes: give --iou-type obb with --format dota");
  if (iou_type == "obb" && format == "coco")
    throw Error("oriented boxes are read from DOTA task-1 or YOLO OBB files: --format dota|yolo");
  if (iou_type == "segm" && format != "coco" && format != "yolo")
    throw Error(
        "masks are read from COCO results files or YOLO polygons: --format coco|yolo with "
        "--iou-type segm");
  if (ap != "voc07" && ap != "voc12" && ap != "coco")
    throw Error("--ap " + ap + ": expected voc07, voc12 or coco");
  if (predictions.empty() && iou_type != "bbox")
    throw Error("--iou-type needs --predictions (coverage compares nothing)");
  if (thin_below < 0) throw Error("--thin must be >= 0");
  if (predictions.empty() && !fail_under.empty())
    throw Error("--fail-under needs --predictions (coverage has no metrics)");
  if (predictions.empty() && !suggest.empty())
    throw Error("--suggest needs --predictions (it asks for frames where the model did worst)");
  for (const std::string& t : fail_under) ParseThreshold(t);
}

EvaluationReport CoverageReport(const EvaluationTruth& truth, int64_t thin_below) {
  EvaluationReport report = BaseReport(truth, thin_below);
  report.coverage = EvaluateImages(truth, BinConditions(truth), nullptr, thin_below).coverage;
  return report;
}

EvaluationReport Evaluate(const EvaluationTruth& truth,
                          std::vector<DetectionBox> detections,
                          int64_t thin_below,
                          uint64_t memory_budget) {
  DetectionsByImage by_image(SpillShare(memory_budget));
  for (DetectionBox& d : detections) by_image.Add(std::move(d));
  std::vector<DetectionBox>().swap(detections);
  return Evaluate(truth, &by_image, thin_below, memory_budget);
}

EvaluationReport Evaluate(const EvaluationTruth& truth,
                          DetectionsByImage* detections,
                          int64_t thin_below,
                          uint64_t memory_budget) {
  EvaluationReport report = BaseReport(truth, thin_below);
  report.detections = detections->size();
  report.iou_type = truth.coco.iou_type == IouType::kMask   ? "segm"
                    : truth.coco.iou_type == IouType::kQuad ? "obb"
                                                            : "bbox";
  // Each image's detections in file order (the order COCOeval breaks score
  // ties in), image by image.
  ImageMetrics metrics = EvaluateImages(
      truth, BinConditions(truth), detections, thin_below, SpillShare(memory_budget));
  report.stats = metrics.stats;
  report.all = std::move(metrics.all);
  report.strata = std::move(metrics.strata);
  report.coverage = std::move(metrics.coverage);
  return report;
}

EvaluateResult RunEvaluate(const EvaluateOptions& options) {
  options.Check();
  CheckCollectionFolder(options.truth.collection);
  // No output may be, contain or lie inside an input; existing outputs only
  // with --force; all refused before any work.
  OutputGuard guard("lsds evaluate");
  guard.AddInput(options.truth.collection, "collection folder");
  guard.AddInput(options.predictions, "predictions file");
  guard.CheckOutput(options.output, "-o");
  guard.CheckOutput(options.junit, "--junit");
  guard.CheckOutput(options.suggest, "--suggest");
  const std::vector<std::pair<std::filesystem::path, const char*>> outputs = {
      {options.output, "evaluation"},
      {options.junit, "JUnit report"},
      {options.suggest, "capture"}};
  for (size_t i = 0; i < outputs.size(); ++i) {
    if (outputs[i].first.empty()) continue;
    for (size_t j = 0; j < i; ++j)
      if (CanonicalPath(outputs[i].first) == CanonicalPath(outputs[j].first))
        throw Error("two outputs name the same file", Location(outputs[i].first.string()));
    RefuseToOverwrite(outputs[i].first, options.force, outputs[i].second);
  }

  TruthOptions truth_options = options.truth;
  truth_options.masks = options.iou_type == "segm";
  EvaluateResult result;
  std::optional<ObbTruth> obb;
  if (options.iou_type == "obb") obb = ReadObbTruth(truth_options);
  // The annotations stay in the converter's scratch file, read image by image
  // (oriented boxes: held, with their facts).
  EvaluationTruth streamed = obb ? EvaluationTruth() : StreamCollectionTruth(truth_options);
  // MOT's distractor classes are ignored, as TrackEval leaves them out of the
  // truth (mot_challenge_2d_box.py:390-394).
  if (options.format == "mot")
    streamed.ignored_categories = MotDistractorCategories(streamed, options.truth.mot_classes);
  const EvaluationTruth& truth = obb ? obb->truth : streamed;
  if (options.predictions.empty()) {
    result.report = CoverageReport(truth, options.thin_below);
  } else {
    // The detections and the accumulation records each held up to 1/32 of
    // --memory-budget, the rest in a scratch file (docs/evaluate.md, "Memory").
    const uint64_t budget = MemoryBudgetBytes();
    DetectionsByImage detections(SpillShare(budget));
    std::vector<DotaDetection> oriented;
    if (obb) {
      // Oriented boxes: COCO's rules with the devkit's polygon IoU for the
      // metrics and strata; beside them (unless --ap coco) the devkit's own
      // task-1 evaluation of the same objects and result files.
      oriented =
          options.format == "yolo"
              ? ReadYoloObbDetections(options.predictions, truth, obb->dota.class_names)
              : ReadDotaResults(options.predictions, obb->dota.class_names, obb->dota.images);
      for (DetectionBox& d : ObbDetections(*obb, oriented)) detections.Add(std::move(d));
    } else {
      ReadBoxPredictions(options, truth, &detections);
    }
    result.report = Evaluate(truth, &detections, options.thin_below, budget);
    if (obb && options.ap != "coco")
      result.report.dota = EvaluateDota(obb->dota.class_names,
                                        obb->dota.objects,
                                        oriented,
                                        options.ap == "voc07" ? VocAp::k07 : VocAp::k12);
    result.report.predictions = Utf8Escaped(options.predictions.string());
    for (const std::string& t : options.fail_under)
      result.report.thresholds.push_back(ParseThreshold(t));
    result.thresholds_passed = CheckThresholds(*result.report.stats, &result.report.thresholds);
  }
  std::string capture;
  if (!options.suggest.empty()) {
    Suggestion suggestion = SuggestCapture(truth, BinConditions(truth), result.report);
    capture = std::move(suggestion.lcap);
    result.suggested_quotas = std::move(suggestion.quotas);
  }
  result.report.collection = Utf8Escaped(options.truth.collection.string());
  if (!options.output.empty())
    WriteFileAtomic(options.output, ReportJson(result.report).dump(2) + "\n");
  if (!options.junit.empty()) WriteFileAtomic(options.junit, ReportJUnit(result.report));
  if (!options.suggest.empty()) WriteFileAtomic(options.suggest, capture);
  return result;
}

}  // namespace lsds::evaluate
