// lsds evaluate's masks (iouType segm) against the reference COCO API: the 12
// stats of pycocotools' COCOeval(iouType="segm") for five prediction sets on
// the golden collection, equal to 1e-9. The sets use every form of mask COCO
// reads (compressed and uncompressed RLE, polygons, with and without boxes).
// Provenance of the numbers: the README.md of tests/evaluate.
#include <array>
#include <string>

#include <gtest/gtest.h>

#include "evaluate/coco_eval.h"
#include "evaluate/evaluate_run.h"
#include "evaluate/ground_truth.h"
#include "evaluate/predictions.h"
#include "evaluate/segmentation.h"
#include "evaluate/strata.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

struct Golden {
  const char* name;
  std::array<double, 12> stats;  // AP AP50 AP75 APs APm APl AR1 AR10 AR100 ARs ARm ARl
};

// Written by tests/evaluate/make_mask_goldens.py (pycocotools at
// cocodataset/cocoapi 8c9bcc3cf640524c4c20a9c40e89cb6a2f2fa0e9, numpy 1.24.2,
// Debian 12).
const Golden kGoldens[] = {
    {"perfect", {1, 1, 1, 1, 1, 1, 0.17083333333333331, 1, 1, 1, 1, 1}},
    {"jittered",
     {0.23476296224709386,
      0.5050558541206781,
      0.20529763219606112,
      0.16339032060223677,
      0.65987813067020973,
      0.90000000000000002,
      0.06220238095238094,
      0.40827380952380954,
      0.40827380952380954,
      0.28098739495798319,
      0.76875000000000004,
      0.90000000000000002}},
    {"missing_small",
     {0.53876793994919003,
      0.64356435643564358,
      0.64356435643564358,
      0.41934094443704228,
      0.90563118811881194,
      1,
      0.15279761904761904,
      0.55803571428571441,
      0.55803571428571441,
      0.44023109243697467,
      0.90999999999999992,
      1}},
    {"false_positives",
     {0.4416521984754429,
      0.698376045621526,
      0.47747178022788106,
      0.42785805244662667,
      0.53876646067968137,
      1,
      0.094345238095238107,
      0.69958333333333333,
      0.71083333333333332,
      0.63707983193277307,
      0.9212499999999999,
      1}},
    {"crowd",
     {0.61131396812871708,
      0.92746346063177743,
      0.69840482508283908,
      0.53888192079411223,
      0.93633663366336639,
      1,
      0.11392857142857142,
      0.7092857142857143,
      0.72428571428571442,
      0.64600840336134446,
      0.95749999999999991,
      1}},
};

using MaskEvalGolden = GoldenCollection;

TEST_F(MaskEvalGolden, TheTwelveStatsAreThoseOfPycocotools) {
  ASSERT_EQ(mask_truth_->coco.iou_type, IouType::kMask);
  for (const Golden& golden : kGoldens) {
    EvaluationTruth truth = *mask_truth_;
    if (std::string(golden.name) == "crowd") AddCrowdRegions("segm/crowd_regions.json", &truth);
    CocoData data = truth.coco;
    data.detections =
        ReadCocoPredictions(GoldenData("segm/" + std::string(golden.name) + ".json"), truth);
    const CocoStats stats = CocoEvaluator(data).Stats();
    for (size_t i = 0; i < stats.size(); ++i)
      EXPECT_NEAR(stats[i], golden.stats[i], 1e-9) << golden.name << " " << CocoStatNames()[i];
  }
}

TEST_F(MaskEvalGolden, TheStreamedEvaluationGivesTheSameStats) {
  // The masks read image by image from the converter's file (evaluate_run.cc).
  TruthOptions options;
  options.collection = C();
  options.masks = true;
  const EvaluationTruth streamed = StreamCollectionTruth(options);
  ASSERT_TRUE(streamed.streamed);
  for (const Golden& golden : kGoldens) {
    EvaluationTruth held = *mask_truth_;
    const bool crowd = std::string(golden.name) == "crowd";
    if (crowd) AddCrowdRegions("segm/crowd_regions.json", &held);
    const EvaluationTruth& truth = crowd ? held : streamed;
    const EvaluationReport report = Evaluate(
        truth,
        ReadCocoPredictions(GoldenData("segm/" + std::string(golden.name) + ".json"), truth),
        30);
    ASSERT_TRUE(report.stats) << golden.name;
    for (size_t i = 0; i < report.stats->size(); ++i)
      EXPECT_NEAR((*report.stats)[i], golden.stats[i], 1e-9)
          << golden.name << " " << CocoStatNames()[i];
  }
}

TEST_F(MaskEvalGolden, TheSpilledEvaluationGivesTheSameStats) {
  // Masks and records through the scratch file (a budget of a few bytes).
  TruthOptions options;
  options.collection = C();
  options.masks = true;
  const EvaluationTruth streamed = StreamCollectionTruth(options);
  for (const Golden& golden : kGoldens) {
    EvaluationTruth held = *mask_truth_;
    const bool crowd = std::string(golden.name) == "crowd";
    if (crowd) AddCrowdRegions("segm/crowd_regions.json", &held);
    const EvaluationTruth& truth = crowd ? held : streamed;
    DetectionsByImage detections(1024);
    ReadCocoPredictions(GoldenData("segm/" + std::string(golden.name) + ".json"),
                        truth,
                        [&](DetectionBox&& d) { detections.Add(std::move(d)); });
    EXPECT_GT(detections.runs(), 1u) << golden.name;
    const ImageMetrics metrics = EvaluateImages(truth, BinConditions(truth), &detections, 30, 1024);
    EXPECT_GT(metrics.spilled_runs, 1u) << golden.name;
    ASSERT_TRUE(metrics.stats) << golden.name;
    for (size_t i = 0; i < metrics.stats->size(); ++i)
      EXPECT_NEAR((*metrics.stats)[i], golden.stats[i], 1e-9)
          << golden.name << " " << CocoStatNames()[i];
  }
}

TEST_F(MaskEvalGolden, MasksAndBoxesGiveDifferentNumbersOnTheSamePredictions) {
  // The jittered masks scored as boxes (their rleToBbox boxes) differ from the
  // masks' own scores: the segm path is not the box path under another name.
  EvaluationTruth truth = *mask_truth_;
  CocoData masks = truth.coco;
  masks.detections = ReadCocoPredictions(GoldenData("segm/jittered.json"), truth);
  CocoData boxes = masks;
  boxes.iou_type = IouType::kBox;
  EXPECT_NE(CocoEvaluator(masks).Stats()[0], CocoEvaluator(boxes).Stats()[0]);
}

TEST_F(MaskEvalGolden, EveryGroundTruthMaskHasTheConvertersArea) {
  // The converter's `area` is the mask's pixel count; the RLE read back says the same.
  ASSERT_FALSE(mask_truth_->coco.ground_truth.empty());
  for (const GroundTruthBox& g : mask_truth_->coco.ground_truth)
    EXPECT_EQ(static_cast<double>(masks::CocoRleArea(g.mask.counts)), g.area) << g.id;
}

}  // namespace
}  // namespace lsds::evaluate
