// The rules of the COCOeval port on cases small enough to work out by hand.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "evaluate/coco_eval.h"
#include "evaluate/dota_eval.h"

namespace lsds::evaluate {
namespace {

Quad QuadOfTest(const std::vector<double>& v) {
  Quad q{};
  std::copy(v.begin(), v.end(), q.begin());
  return q;
}

GroundTruthBox Gt(int64_t id, int64_t image, BoxXywh box, bool crowd = false) {
  GroundTruthBox g;
  g.id = id;
  g.image_id = image;
  g.category_id = 1;
  g.bbox = box;
  g.area = box.w * box.h;
  g.iscrowd = crowd;
  return g;
}

DetectionBox Dt(int64_t image, BoxXywh box, double score) {
  DetectionBox d;
  d.image_id = image;
  d.category_id = 1;
  d.bbox = box;
  d.score = score;
  return d;
}

TEST(CocoEval, ThresholdsAreNumpysLinspace) {
  EXPECT_EQ(IouThresholds()[0], 0.5);
  EXPECT_EQ(IouThresholds()[9], 0.95);
  // COCOeval finds AP75 with np.where(.75 == iouThrs): the linspace value must be .75 itself.
  EXPECT_EQ(IouIndex(0.75), 5);
  EXPECT_EQ(IouIndex(0.5), 0);
  EXPECT_FALSE(IouIndex(0.72).has_value());
  EXPECT_EQ(IouIndex(0.7), 4);
  EXPECT_EQ(RecallThresholds()[100], 1.0);
  EXPECT_EQ(RecallThresholds()[1], 0.01);
}

TEST(CocoEval, OnePerfectDetectionIsOneEverywhereItCounts) {
  CocoData data{{1}, {1}, {Gt(1, 1, {0, 0, 10, 10})}, {Dt(1, {0, 0, 10, 10}, 0.9)}};
  const CocoStats s = CocoEvaluator(data).Stats();
  // Precision is tp / (tp + fp + np.spacing(1)): 1 - 2^-52 for one true positive.
  EXPECT_NEAR(s[0], 1, 1e-15);  // AP
  EXPECT_NEAR(s[3], 1, 1e-15);  // APs: area 100 < 32^2
  EXPECT_EQ(s[4], -1);          // APm: no ground truth there
  EXPECT_EQ(s[5], -1);
  EXPECT_EQ(s[8], 1);  // AR100
}

TEST(CocoEval, OrientedBoxesAreComparedByTheirPolygons) {
  // A 10 x 10 square turned 45 degrees about (5, 5), and the same square slid
  // 3 px along one of its sides: polygon IoU 70 / 130 = 0.538, a match at .50
  // only (AP .1). Their upright boxes (IoU 0.566) would match at .55 too.
  const double r = 5 * std::sqrt(2.0), s = 3 / std::sqrt(2.0);
  const auto diamond = [&](double d) {
    return std::vector<double>{
        5 + d, 5 - r + d, 5 + r + d, 5 + d, 5 + d, 5 + r + d, 5 - r + d, 5 + d};
  };
  GroundTruthBox g = Gt(1, 1, {5 - r, 5 - r, 2 * r, 2 * r});
  g.quad = diamond(0);
  g.area = 100;
  DetectionBox d = Dt(1, {5 - r + s, 5 - r + s, 2 * r, 2 * r}, 0.9);
  d.quad = diamond(s);
  d.area = 100;
  EXPECT_NEAR(QuadIou(QuadOfTest(g.quad), QuadOfTest(d.quad)), 70.0 / 130.0, 1e-12);
  // A difficult object and a detection on it: ignored, they change nothing.
  GroundTruthBox difficult = Gt(2, 1, {50, 50, 10, 10});
  difficult.quad = {50, 50, 60, 50, 60, 60, 50, 60};
  difficult.ignored = true;
  DetectionBox on_difficult = Dt(1, {50, 50, 10, 10}, 0.95);
  on_difficult.quad = difficult.quad;
  CocoData data{{1}, {1}, {g, difficult}, {d, on_difficult}, IouType::kQuad};
  const CocoStats stats = CocoEvaluator(data).Stats();
  const double one = 1 / (1 + std::numeric_limits<double>::epsilon());  // tp / (tp + eps)
  EXPECT_NEAR(stats[0], 0.1 * one, 1e-15);  // AP: 1 of 10 thresholds at precision 1
  EXPECT_NEAR(stats[1], one, 1e-15);        // AP50
  EXPECT_EQ(stats[2], 0);                   // AP75
  EXPECT_NEAR(stats[8], 0.1, 1e-15);        // AR100
  data.iou_type = IouType::kBox;            // the upright boxes: .50 and .55
  EXPECT_NEAR(CocoEvaluator(data).Stats()[0], 0.2 * one, 1e-15);
}

TEST(CocoEval, IouDecidesTheThresholdsAMatchPasses) {
  // IoU = 58 / 100: a match at .50 and .55 only.
  CocoData data{{1}, {1}, {Gt(1, 1, {0, 0, 10, 10})}, {Dt(1, {0, 0, 5.8, 10}, 0.9)}};
  const CocoEvaluator e(data);
  const Accumulation a = e.Accumulate(Selection{});
  EXPECT_EQ(a.Recall(0, 0, 2), 1);
  EXPECT_EQ(a.Recall(1, 0, 2), 1);
  EXPECT_EQ(a.Recall(2, 0, 2), 0);
  EXPECT_NEAR(e.Stats()[0], 0.2, 1e-12);  // 2 of 10 thresholds at precision 1
}

TEST(CocoEval, DetectionsOnACrowdRegionAreIgnored) {
  CocoData data{
      {1},
      {1},
      {Gt(1, 1, {0, 0, 10, 10}), Gt(2, 1, {50, 50, 40, 40}, true)},
      {Dt(1, {55, 55, 10, 10}, 0.99), Dt(1, {60, 60, 10, 10}, 0.98), Dt(1, {0, 0, 10, 10}, 0.5)}};
  const CocoStats with_crowd = CocoEvaluator(data).Stats();
  EXPECT_NEAR(
      with_crowd[0], 1, 1e-15);  // the two boxes inside the crowd region are not false positives
  data.ground_truth.pop_back();
  EXPECT_LT(CocoEvaluator(data).Stats()[0], 1);
}

TEST(CocoEval, OnlyTheBestScoredDetectionsPerImageCount) {
  // maxDets 1: the higher-scored false positive hides the true positive.
  CocoData data{{1},
                {1},
                {Gt(1, 1, {0, 0, 10, 10})},
                {Dt(1, {0, 0, 10, 10}, 0.5), Dt(1, {40, 40, 10, 10}, 0.6)}};
  const CocoStats s = CocoEvaluator(data).Stats();
  EXPECT_EQ(s[6], 0);  // AR1
  EXPECT_EQ(s[7], 1);  // AR10
}

TEST(CocoEval, ASelectionCountsItsObjectsOnly) {
  CocoData data{{1, 2},
                {1},
                {Gt(1, 1, {0, 0, 10, 10}), Gt(2, 2, {0, 0, 10, 10})},
                {Dt(1, {0, 0, 10, 10}, 0.9)}};
  const CocoEvaluator e(data);
  Selection image2;
  image2.image = [](int64_t image) { return image == 2; };
  const Accumulation a = e.Accumulate(image2);
  EXPECT_EQ(a.ground_truth, 1);
  EXPECT_EQ(a.matched_50, 0);
  Selection first;
  first.ground_truth = [](size_t i) { return i == 0; };
  const Accumulation b = e.Accumulate(first);
  EXPECT_EQ(b.ground_truth, 1);
  EXPECT_EQ(b.matched_50, 1);
}

}  // namespace
}  // namespace lsds::evaluate
