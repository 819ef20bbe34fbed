// accumulate's order and precision envelope on cases worked out by hand from
// cocoeval.py (cocoapi 8c9bcc3, :362-410), through the whole-memory evaluator,
// the image-by-image evaluation in memory, and the same with every record
// and detection spilled to sorted runs on a scratch file.
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluate/accumulation.h"
#include "evaluate/coco_eval.h"
#include "evaluate/detections_by_image.h"
#include "evaluate/ground_truth.h"
#include "evaluate/strata.h"

namespace lsds::evaluate {
namespace {

namespace fs = std::filesystem;

GroundTruthBox Gt(int64_t id, int64_t image, BoxXywh box) {
  GroundTruthBox g;
  g.id = id;
  g.image_id = image;
  g.category_id = 1;
  g.bbox = box;
  g.area = box.w * box.h;
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

EvaluationTruth TruthOf(const CocoData& data) {
  EvaluationTruth truth;
  truth.coco = data;
  truth.coco.detections.clear();
  truth.category_names = {"thing"};
  return truth;
}

// The accumulation of everything (no area range) three ways: CocoEvaluator
// over the whole data; EvaluateImages image by image in memory; and the same
// with a few bytes of memory, so that every detection and record is spilled.
struct ThreeWays {
  Accumulation whole, streamed, spilled;
  size_t spilled_runs = 0, detection_runs = 0;
};

ThreeWays Accumulate(const CocoData& data) {
  ThreeWays out;
  out.whole = CocoEvaluator(data).Accumulate(Selection{});
  const EvaluationTruth truth = TruthOf(data);
  out.streamed = EvaluateImages(truth, {}, &data.detections, 30).all;
  DetectionsByImage detections(1);
  for (const DetectionBox& d : data.detections) detections.Add(d);
  out.detection_runs = detections.runs();
  const ImageMetrics spilled = EvaluateImages(truth, {}, &detections, 30, 1);
  out.spilled = spilled.all;
  out.spilled_runs = spilled.spilled_runs;
  return out;
}

// Precision at recall threshold r (IoU .5, maxDets 100), one category.
double P(const Accumulation& a, int r) { return a.Precision(0, r, 0, 2); }
double Score(const Accumulation& a, int r) { return a.scores[(r * a.categories + 0) * 3 + 2]; }

constexpr double kEps = std::numeric_limits<double>::epsilon();

TEST(Accumulation, ScoreTiesAcrossImagesFollowTheImageOrder) {
  // Image 1 holds the only object; image 1's detection finds it, image 2's
  // is a false positive, both scored .5, and the file lists image 2 first.
  // accumulate concatenates the images in id order and sorts stably: the true
  // positive first, rc = [1, 1], pr = [1, .5], so every q is 1 - eps. With
  // image 2 first it would be .5.
  CocoData data{{1, 2},
                {1},
                {Gt(1, 1, {0, 0, 10, 10})},
                {Dt(2, {50, 50, 10, 10}, 0.5), Dt(1, {0, 0, 10, 10}, 0.5)}};
  const ThreeWays a = Accumulate(data);
  EXPECT_GT(a.spilled_runs, 0u);
  EXPECT_GT(a.detection_runs, 0u);
  for (const Accumulation* x : {&a.whole, &a.streamed, &a.spilled}) {
    for (int r = 0; r < kRecallThresholdCount; ++r) EXPECT_EQ(P(*x, r), 1 / (1 + kEps)) << r;
    EXPECT_EQ(x->Recall(0, 0, 2), 1);
    EXPECT_EQ(x->false_positives_50, 1);
  }
  // Swapped ids: the false positive's image comes first, q = .5 everywhere.
  data.image_ids = {1, 2};
  data.ground_truth[0].image_id = 2;
  data.detections = {Dt(2, {0, 0, 10, 10}, 0.5), Dt(1, {50, 50, 10, 10}, 0.5)};
  const ThreeWays b = Accumulate(data);
  for (const Accumulation* x : {&b.whole, &b.streamed, &b.spilled})
    for (int r = 0; r < kRecallThresholdCount; ++r) EXPECT_EQ(P(*x, r), 1 / (2 + kEps)) << r;
}

TEST(Accumulation, ScoreTiesInAnImageFollowTheFileOrder) {
  // One image, one object, a miss and a hit scored alike: the file's order
  // decides (evaluateImg's mergesort keeps it, :173-176), and so the
  // precision: miss first .5, hit first 1.
  const BoxXywh object{0, 0, 10, 10}, miss{50, 50, 10, 10};
  CocoData miss_first{{1}, {1}, {Gt(1, 1, object)}, {Dt(1, miss, 0.7), Dt(1, object, 0.7)}};
  CocoData hit_first{{1}, {1}, {Gt(1, 1, object)}, {Dt(1, object, 0.7), Dt(1, miss, 0.7)}};
  const ThreeWays a = Accumulate(miss_first), b = Accumulate(hit_first);
  for (const ThreeWays* w : {&a, &b}) {
    const double expected = w == &a ? 1 / (2 + kEps) : 1 / (1 + kEps);
    for (const Accumulation* x : {&w->whole, &w->streamed, &w->spilled})
      for (int r = 0; r < kRecallThresholdCount; ++r) EXPECT_EQ(P(*x, r), expected) << r;
  }
}

TEST(Accumulation, TheEnvelopeAndTheScoreAtEachRecallThreshold) {
  // Two objects; a hit (.9), a miss (.8), a hit (.7): rc = [.5, .5, 1],
  // pr = [1, .5, 2/3], made non-increasing from the right [1, 2/3, 2/3]. A
  // threshold up to .5 is reached at the first detection (q = 1, score .9),
  // above it at the third (q = 2/3, score .7).
  CocoData data{
      {1},
      {1},
      {Gt(1, 1, {0, 0, 10, 10}), Gt(2, 1, {100, 100, 10, 10})},
      {Dt(1, {0, 0, 10, 10}, 0.9), Dt(1, {50, 50, 10, 10}, 0.8), Dt(1, {100, 100, 10, 10}, 0.7)}};
  const ThreeWays w = Accumulate(data);
  for (const Accumulation* x : {&w.whole, &w.streamed, &w.spilled}) {
    for (int r = 0; r <= 50; ++r) {
      EXPECT_EQ(P(*x, r), 1 / (1 + kEps)) << r;
      EXPECT_EQ(Score(*x, r), 0.9) << r;
    }
    for (int r = 51; r < kRecallThresholdCount; ++r) {
      EXPECT_EQ(P(*x, r), 2 / (3 + kEps)) << r;
      EXPECT_EQ(Score(*x, r), 0.7) << r;
    }
    EXPECT_EQ(x->Recall(0, 0, 2), 1);
    // maxDets 1: only the .9 hit; recall .5, nothing reached above it.
    EXPECT_EQ(x->Recall(0, 0, 0), 0.5);
    EXPECT_EQ(x->Precision(0, 50, 0, 0), 1 / (1 + kEps));
    EXPECT_EQ(x->Precision(0, 51, 0, 0), 0);
  }
}

TEST(Accumulation, TheScratchFileLeavesNothingBehind) {
  // The spill file is unlinked as soon as it is made: the temporary folder
  // holds nothing while the evaluation runs, after it, or after an error.
  const fs::path folder = fs::temp_directory_path() / "lsds-accumulation-test";
  fs::remove_all(folder);
  fs::create_directories(folder);
  const char* previous = std::getenv("TMPDIR");
  const std::string saved = previous ? previous : "";
  setenv("TMPDIR", folder.c_str(), 1);
  {
    DetectionsByImage detections(1);
    for (int i = 0; i < 10; ++i) detections.Add(Dt(1 + i % 2, {0, 0, 10, 10}, 0.1 * i));
    EXPECT_GT(detections.runs(), 0u);
    EXPECT_TRUE(fs::is_empty(folder));
    const EvaluationTruth truth = TruthOf({{1, 2}, {1}, {Gt(1, 1, {0, 0, 10, 10})}, {}});
    EXPECT_GT(EvaluateImages(truth, {}, &detections, 30, 1).spilled_runs, 0u);
  }
  EXPECT_TRUE(fs::is_empty(folder));
  if (previous) {
    setenv("TMPDIR", saved.c_str(), 1);
  } else {
    unsetenv("TMPDIR");
  }
  fs::remove_all(folder);
}

}  // namespace
}  // namespace lsds::evaluate
