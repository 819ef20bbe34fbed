// lsds evaluate --iou-type obb against the DOTA devkit's own task-1
// evaluation: per-class VOC AP (07 and 10-12) and their mean for four
// prediction sets on the golden collection, equal to 1e-9, and polyiou's IoU
// of quadrilaterals. Provenance of the numbers: the README.md of tests/evaluate.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluate/dota_eval.h"
#include "evaluate/dota_files.h"
#include "evaluate/ground_truth.h"
#include "evaluate/obb_truth.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

struct Golden {
  const char* name;
  VocAp ap;
  std::vector<double> class_aps;  // box, crate
  double map;
};

// Written by tests/evaluate/make_obb_goldens.py (DOTA_devkit at CAPTAIN-WHU
// 99388551054be9a6dabb01c8bb2a7eb562d57b4f, polyiou built with SWIG 4.1.0,
// numpy 1.24.2, Debian 12).
const Golden kGoldens[] = {
    {"perfect", VocAp::k07, {1.0000000000000002, 1.0000000000000002}, 1.0000000000000002},
    {"perfect", VocAp::k12, {1, 1}, 1},
    {"jittered", VocAp::k07, {0.71572545101956853, 0.7524294927040921}, 0.73407747186183037},
    {"jittered", VocAp::k12, {0.70850950066636365, 0.76682000653808435}, 0.73766475360222405},
    {"missing_small", VocAp::k07, {1.0000000000000002, 0.90909090909090928}, 0.95454545454545481},
    {"missing_small", VocAp::k12, {1, 0.95999999999999996}, 0.97999999999999998},
    {"false_positives", VocAp::k07, {0.61618441275558966, 0.6106665566738162}, 0.61342548471470293},
    {"false_positives",
     VocAp::k12,
     {0.62840640690396143, 0.63220471279122947},
     0.63030555984759551},
};

using DotaEvalGolden = GoldenCollection;

TEST_F(DotaEvalGolden, ClassApsAndTheirMeanAreThoseOfTheDevkit) {
  TruthOptions options;
  options.collection = C();
  const DotaTruth truth = ReadObbTruth(options).dota;
  ASSERT_EQ(truth.class_names, (std::vector<std::string>{"box", "crate"}));
  int difficult = 0;
  for (const DotaObject& o : truth.objects) difficult += o.difficult;
  EXPECT_GT(difficult, 0);  // the goldens reach the devkit's difficult rule
  for (const Golden& golden : kGoldens) {
    const std::vector<DotaDetection> detections = ReadDotaResults(
        GoldenData(std::string("obb/") + golden.name), truth.class_names, truth.images);
    const DotaResult result = EvaluateDota(truth.class_names, truth.objects, detections, golden.ap);
    ASSERT_EQ(result.classes.size(), golden.class_aps.size());
    for (size_t k = 0; k < golden.class_aps.size(); ++k) {
      ASSERT_TRUE(result.classes[k].ap.has_value()) << golden.name;
      EXPECT_NEAR(*result.classes[k].ap, golden.class_aps[k], 1e-9)
          << golden.name << " " << result.classes[k].class_name;
    }
    ASSERT_TRUE(result.map.has_value());
    EXPECT_NEAR(*result.map, golden.map, 1e-9) << golden.name;
  }
}

TEST(DotaQuadIou, EqualsPolyiou) {
  // polyiou.iou_poly of the devkit (as above) on these pairs.
  struct Case {
    Quad p, q;
    double iou;
  };
  const Case cases[] = {
      {{0, 0, 10, 0, 10, 10, 0, 10}, {5, 5, 15, 5, 15, 15, 5, 15}, 0.14285714285714285},
      {{0, 0, 10, 0, 10, 10, 0, 10}, {0, 10, 10, 10, 10, 0, 0, 0}, 1.0},  // other winding
      {{0, 0, 10, 0, 10, 10, 0, 10}, {5, -2, 12, 5, 5, 12, -2, 5}, 0.7068965517241379},
      {{25.63, 36.27, 36.49, 34.95, 37.54, 43.63, 26.69, 44.95},
       {26, 36, 36, 36, 36, 44, 26, 44},
       0.8047170801168204},
      {{0, 0, 4, 0, 4, 4, 0, 4}, {10, 10, 14, 10, 14, 14, 10, 14}, 0.0},
  };
  for (const Case& c : cases) EXPECT_NEAR(QuadIou(c.p, c.q), c.iou, 1e-12);
}

}  // namespace
}  // namespace lsds::evaluate
