// lsds evaluate's COCOeval port against the reference COCO API: the 12 stats of
// pycocotools' COCOeval (iouType bbox) for five prediction sets on the golden
// collection, equal to 1e-9. Provenance of the numbers: the README.md of tests/evaluate.
#include <array>
#include <string>

#include <gtest/gtest.h>

#include "evaluate/coco_eval.h"
#include "evaluate/evaluate_run.h"
#include "evaluate/ground_truth.h"
#include "evaluate/predictions.h"
#include "evaluate/strata.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

struct Golden {
  const char* name;
  std::array<double, 12>
      stats;  // COCOeval.stats: AP AP50 AP75 APs APm APl AR1 AR10 AR100 ARs ARm ARl
};

// Written by tests/evaluate/make_goldens.py (pycocotools at cocodataset/cocoapi
// 8c9bcc3cf640524c4c20a9c40e89cb6a2f2fa0e9, numpy 1.24.2, Debian 12).
const Golden kGoldens[] = {
    {"perfect", {1, 1, 1, 1, 1, 1, 0.17083333333333331, 1, 1, 1, 1, 1}},
    {"jittered",
     {0.28678031051121944,
      0.77251641204220689,
      0.11157864189438688,
      0.26491120278659192,
      0.35031038818167531,
      0.50099009900990099,
      0.059880952380952368,
      0.38244047619047616,
      0.38244047619047616,
      0.36869747899159661,
      0.40750000000000003,
      0.5}},
    {"missing_small",
     {0.52046099246458188,
      0.64356435643564358,
      0.64356435643564358,
      0.43134517297883634,
      0.79382602545968883,
      0.95049504950495045,
      0.14624999999999999,
      0.54398809523809533,
      0.54398809523809533,
      0.44810924369747901,
      0.82499999999999996,
      0.94999999999999996}},
    {"false_positives",
     {0.49985444797851514,
      0.77974787109969823,
      0.60227256350952518,
      0.55002603427972918,
      0.47378261933336185,
      0.7504950495049505,
      0.092321428571428568,
      0.71398809523809526,
      0.71398809523809526,
      0.70420168067226896,
      0.73250000000000004,
      0.80000000000000004}},
    {"crowd",
     {0.64699110691161255,
      1,
      0.82438860245471546,
      0.64467481024874207,
      0.69271570014144268,
      0.60099009900990097,
      0.11845238095238093,
      0.69000000000000006,
      0.70750000000000002,
      0.69999999999999996,
      0.73999999999999999,
      0.59999999999999998}},
};

using CocoEvalGolden = GoldenCollection;

TEST_F(CocoEvalGolden, TheTwelveStatsAreThoseOfPycocotools) {
  ASSERT_GT(std::size(kGoldens), 0u);
  for (const Golden& golden : kGoldens) {
    EvaluationTruth truth = *truth_;
    if (std::string(golden.name) == "crowd") AddCrowdRegions("crowd_regions.json", &truth);
    CocoData data = truth.coco;
    data.detections = ReadCocoPredictions(GoldenData(std::string(golden.name) + ".json"), truth);
    const CocoStats stats = CocoEvaluator(data).Stats();
    for (size_t i = 0; i < stats.size(); ++i)
      EXPECT_NEAR(stats[i], golden.stats[i], 1e-9) << golden.name << " " << CocoStatNames()[i];
  }
}

TEST_F(CocoEvalGolden, TheStreamedEvaluationGivesTheSameStats) {
  // What `lsds evaluate` runs: the truth streamed image by image from the
  // converter's file, each image matched as soon as its detections are known
  // (evaluate_run.cc); the crowd set adds regions to the truth held in memory.
  TruthOptions options;
  options.collection = C();
  const EvaluationTruth streamed = StreamCollectionTruth(options);
  ASSERT_TRUE(streamed.streamed);
  EXPECT_TRUE(streamed.coco.ground_truth.empty());
  EXPECT_EQ(streamed.AnnotationCount(), truth_->AnnotationCount());
  for (const Golden& golden : kGoldens) {
    EvaluationTruth held = *truth_;
    const bool crowd = std::string(golden.name) == "crowd";
    if (crowd) AddCrowdRegions("crowd_regions.json", &held);
    const EvaluationTruth& truth = crowd ? held : streamed;
    const EvaluationReport report = Evaluate(
        truth, ReadCocoPredictions(GoldenData(std::string(golden.name) + ".json"), truth), 30);
    ASSERT_TRUE(report.stats) << golden.name;
    for (size_t i = 0; i < report.stats->size(); ++i)
      EXPECT_NEAR((*report.stats)[i], golden.stats[i], 1e-9)
          << golden.name << " " << CocoStatNames()[i];
  }
}

TEST_F(CocoEvalGolden, TheSpilledEvaluationGivesTheSameStats) {
  // The same with a memory budget of a few bytes: every detection read goes to
  // a run sorted by image on the scratch file, every accumulation record of
  // every selection (area ranges and strata) to sorted runs merged at the end.
  TruthOptions options;
  options.collection = C();
  const EvaluationTruth streamed = StreamCollectionTruth(options);
  for (const Golden& golden : kGoldens) {
    EvaluationTruth held = *truth_;
    const bool crowd = std::string(golden.name) == "crowd";
    if (crowd) AddCrowdRegions("crowd_regions.json", &held);
    const EvaluationTruth& truth = crowd ? held : streamed;
    DetectionsByImage detections(1024);
    ReadCocoPredictions(GoldenData(std::string(golden.name) + ".json"),
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

TEST_F(CocoEvalGolden, TheCollectionCoversEveryAreaRangeAndBothClasses) {
  // The goldens mean something only if the truth reaches every COCO area range.
  int small = 0, medium = 0, large = 0;
  for (const GroundTruthBox& g : truth_->coco.ground_truth) {
    small += g.area < 32 * 32;
    medium += g.area >= 32 * 32 && g.area <= 96 * 96;
    large += g.area > 96 * 96;
  }
  EXPECT_GE(small, 10);
  EXPECT_GE(medium, 10);
  EXPECT_GE(large, 2);
  EXPECT_EQ(truth_->category_names, (std::vector<std::string>{"box", "crate"}));
  // Image ids are frame index + 1 (lsds convert --to coco).
  EXPECT_EQ(truth_->coco.image_ids.front(), 1);
  EXPECT_EQ(truth_->images.At(7).frame, 6);
}

}  // namespace
}  // namespace lsds::evaluate
