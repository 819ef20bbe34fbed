// lsds evaluate on the golden collection: strata ranked by what the model
// misses, coverage of the condition space, bad predictions named at their
// entry, and the command end to end (outputs, exit codes, thresholds).
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "evaluate/conditions.h"
#include "evaluate/evaluate_run.h"
#include "evaluate/predictions.h"
#include "evaluate/strata.h"
#include "libs/collection/schema.h"
#include "libs/util/atomic_file.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

namespace fs = std::filesystem;

class EvaluateOnGolden : public GoldenCollection {
 protected:
  static EvaluationReport Report(const std::string& predictions) {
    return Evaluate(*truth_, ReadCocoPredictions(GoldenData(predictions), *truth_), 30);
  }
  static const ConditionMetrics& Condition(const EvaluationReport& r, const std::string& name) {
    for (const ConditionMetrics& c : r.strata)
      if (c.name == name) return c;
    throw std::runtime_error("no condition " + name);
  }
};

TEST_F(EvaluateOnGolden, AModelBlindToSmallObjectsHasItsSmallStrataRankedWorst) {
  // missing_small.json: every object of 16 px and more, none smaller.
  const EvaluationReport r = Report("missing_small.json");
  const ConditionMetrics& size = Condition(r, "size_px");
  ASSERT_GE(size.strata.size(), 3u);
  int64_t small = 0;
  for (const StratumMetrics& s : size.strata) {
    const bool below_16 = s.label == "[0, 8)" || s.label == "[8, 16)";
    EXPECT_EQ(s.recall_50, below_16 ? 0.0 : 1.0) << s.label;
    if (below_16) small += s.objects;
    EXPECT_LE(s.recall_50_ci.low, s.recall_50);
    EXPECT_GE(s.recall_50_ci.high, s.recall_50);
  }
  ASSERT_GT(small, 0);
  EXPECT_TRUE(size.strata.front().label == "[0, 8)" || size.strata.front().label == "[8, 16)");
  EXPECT_EQ(size.strata.back().recall_50, 1.0);
  // The overall counts: every object of 16 px and more matched.
  EXPECT_EQ(r.all.matched_50, r.all.ground_truth - small);
}

TEST_F(EvaluateOnGolden, EveryRecordedConditionIsBrokenDown) {
  const EvaluationReport r = Report("jittered.json");
  std::vector<std::string> names;
  for (const ConditionMetrics& c : r.strata) names.push_back(c.name);
  for (const char* expected :
       {"size_px", "visibility", "in_frame", "class", "distance_m", "off_nadir_deg"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  // Objects of an object condition add up to all objects counted.
  for (const char* name : {"size_px", "class", "in_frame"}) {
    int64_t objects = 0;
    for (const StratumMetrics& s : Condition(r, name).strata) objects += s.objects;
    EXPECT_EQ(objects, r.all.ground_truth) << name;
  }
  const ConditionMetrics& in_frame = Condition(r, "in_frame");
  EXPECT_EQ(in_frame.strata.size(), 2u);  // frame 1 cuts objects at the border
}

TEST_F(EvaluateOnGolden, EveryStratumIsTheAccumulationOfItsSelectionOverAllImages) {
  // The report evaluates each image once, for every stratum at once, as the
  // truth streams by; CocoEvaluator holds every box and accumulates one
  // selection over all of them. Each stratum must be that selection's numbers.
  const std::vector<DetectionBox> detections =
      ReadCocoPredictions(GoldenData("jittered.json"), *truth_);
  const EvaluationReport r = Evaluate(*truth_, detections, 30);
  CocoData data = truth_->coco;
  data.detections = detections;
  const CocoEvaluator evaluator(data);
  const std::vector<ConditionBins> conditions = BinConditions(*truth_);
  int64_t compared = 0;
  for (const ConditionBins& c : conditions) {
    const ConditionMetrics& metrics = Condition(r, c.name);
    for (int bin = 0; bin < static_cast<int>(c.bins.size()); ++bin) {
      Selection s;
      if (c.level == Level::kFrame) {
        s.image = [&, bin](int64_t image) { return ImageBin(c, *truth_, image) == bin; };
      } else {
        s.ground_truth = [&, bin](size_t i) {
          const GroundTruthBox& g = truth_->coco.ground_truth[i];
          return ObjectBin(c, {truth_->objects[i], CategoryName(*truth_, g.category_id)}) == bin;
        };
        if (c.bins_detections)
          s.detection = [&, bin](size_t i) { return DetectionBin(c, detections[i]) == bin; };
      }
      const Accumulation a = evaluator.Accumulate(s);
      const auto stratum =
          std::find_if(metrics.strata.begin(), metrics.strata.end(), [&](const StratumMetrics& m) {
            return m.label == c.bins[bin];
          });
      if (stratum == metrics.strata.end()) {
        EXPECT_EQ(a.ground_truth, 0) << c.name << " " << c.bins[bin];
        continue;
      }
      EXPECT_EQ(stratum->objects, a.ground_truth) << c.name << " " << c.bins[bin];
      EXPECT_EQ(stratum->matched_50, a.matched_50) << c.name << " " << c.bins[bin];
      EXPECT_EQ(stratum->false_positives_50, a.false_positives_50) << c.name << " " << c.bins[bin];
      EXPECT_EQ(stratum->ap, MeanPrecision(a, std::nullopt, 2)) << c.name << " " << c.bins[bin];
      EXPECT_EQ(stratum->ap50, MeanPrecision(a, 0, 2)) << c.name << " " << c.bins[bin];
      EXPECT_EQ(stratum->ar100, MeanRecall(a, std::nullopt, 2)) << c.name << " " << c.bins[bin];
      ++compared;
    }
  }
  int64_t reported = 0;
  for (const ConditionMetrics& c : r.strata) reported += static_cast<int64_t>(c.strata.size());
  EXPECT_EQ(compared, reported);
  EXPECT_GE(compared, 15);
  // And the report's twelve numbers are the evaluator's.
  ASSERT_TRUE(r.stats);
  EXPECT_EQ(*r.stats, evaluator.Stats());
}

TEST_F(EvaluateOnGolden, SpilledStrataEqualTheInMemoryOnes) {
  // A budget of 4 KiB (1 KiB each for the detections and the records) puts
  // nearly everything on the scratch file; every number of every stratum is
  // that of the evaluation held in memory, exactly.
  const std::vector<DetectionBox> detections =
      ReadCocoPredictions(GoldenData("jittered.json"), *truth_);
  const EvaluationReport held = Evaluate(*truth_, detections, 30);
  const EvaluationReport spilled = Evaluate(*truth_, detections, 30, 4096);
  ASSERT_TRUE(held.stats && spilled.stats);
  EXPECT_EQ(*held.stats, *spilled.stats);
  EXPECT_EQ(held.all.precision, spilled.all.precision);
  EXPECT_EQ(held.all.recall, spilled.all.recall);
  EXPECT_EQ(held.all.scores, spilled.all.scores);
  ASSERT_EQ(held.strata.size(), spilled.strata.size());
  int64_t compared = 0;
  for (size_t c = 0; c < held.strata.size(); ++c) {
    ASSERT_EQ(held.strata[c].strata.size(), spilled.strata[c].strata.size());
    for (size_t i = 0; i < held.strata[c].strata.size(); ++i) {
      const StratumMetrics& a = held.strata[c].strata[i];
      const StratumMetrics& b = spilled.strata[c].strata[i];
      const std::string at = held.strata[c].name + " " + a.label;
      EXPECT_EQ(a.label, b.label) << at;
      EXPECT_EQ(a.objects, b.objects) << at;
      EXPECT_EQ(a.frames, b.frames) << at;
      EXPECT_EQ(a.matched_50, b.matched_50) << at;
      EXPECT_EQ(a.false_positives_50, b.false_positives_50) << at;
      EXPECT_EQ(a.ap, b.ap) << at;
      EXPECT_EQ(a.ap50, b.ap50) << at;
      EXPECT_EQ(a.ar100, b.ar100) << at;
      ++compared;
    }
  }
  EXPECT_GE(compared, 15);
  // The records did go to the scratch file at that budget.
  DetectionsByImage by_image(1024);
  for (const DetectionBox& d : detections) by_image.Add(d);
  EXPECT_GT(by_image.runs(), 1u);
  EXPECT_GT(EvaluateImages(*truth_, BinConditions(*truth_), &by_image, 30, 1024).spilled_runs, 1u);
}

TEST(EvaluateWilson, TheIntervalOfTheWilsonScore) {
  const Interval half = WilsonInterval(5, 10);
  EXPECT_NEAR(half.low, 0.23659309, 1e-7);
  EXPECT_NEAR(half.high, 0.76340691, 1e-7);
  const Interval none = WilsonInterval(0, 20);
  EXPECT_EQ(none.low, 0);
  EXPECT_NEAR(none.high, 0.16112516, 1e-7);
}

TEST_F(EvaluateOnGolden, CoverageCountsEveryObjectAndFlagsTheHoles) {
  const EvaluationReport r = CoverageReport(*truth_, 30);
  ASSERT_FALSE(r.coverage.empty());
  for (const ConditionCoverage& c : r.coverage) {
    int64_t objects = 0;
    for (const CoverageCell& cell : c.cells) objects += cell.objects;
    EXPECT_EQ(objects + (c.level == Level::kObject ? c.unrecorded : 0), r.annotations) << c.name;
  }
  const ConditionCoverage* off_nadir = nullptr;
  for (const ConditionCoverage& c : r.coverage)
    if (c.name == "off_nadir_deg") off_nadir = &c;
  ASSERT_NE(off_nadir, nullptr);
  EXPECT_EQ(off_nadir->cells.front().frames, 6);  // the nadir frames
  EXPECT_EQ(off_nadir->cells.front().flag, "thin");
  EXPECT_EQ(off_nadir->cells[1].flag, "empty");  // [10, 20): no frame
}

struct BadCase {
  std::string text;
  std::string where;  // the location the message must name
  std::string what;
};

TEST_F(EvaluateOnGolden, BadPredictionsAreNamedAtTheirEntry) {
  const std::string ok = R"({"image_id":1,"category_id":1,"bbox":[1,2,3,4],"score":0.5})";
  const BadCase cases[] = {
      {"", "p.json", "empty"},
      {"{}", "p.json#/", "expected a JSON list"},
      {"[" + ok + ",3]", "p.json#/1", "expected an object"},
      {R"([{"image_id":999,"category_id":1,"bbox":[1,2,3,4],"score":0.5}])",
       "#/0/image_id",
       "not an image of the ground truth"},
      {R"([{"file_name":"x.png","category_id":1,"bbox":[1,2,3,4],"score":0.5}])",
       "#/0/file_name",
       "not an image"},
      {R"([{"image_id":1,"category_id":9,"bbox":[1,2,3,4],"score":0.5}])",
       "#/0/category_id",
       "not a category"},
      {"[" + ok + R"(,{"image_id":1,"category_id":1,"bbox":[1,2,3,4],"score":NaN}])",
       "#/1/score",
       "NaN"},
      {R"([{"image_id":1,"category_id":1,"bbox":[1,2,-3,4],"score":0.5}])",
       "#/0/bbox/2",
       "negative"},
      {R"([{"image_id":1,"category_id":1,"bbox":[1,Infinity,3,4],"score":0.5}])",
       "#/0/bbox/1",
       "Infinity"},
      {R"([{"image_id":1,"category_id":1,"bbox":[1,2,3],"score":0.5}])",
       "#/0/bbox",
       "expected [x, y, width, height]"},
      {R"([{"image_id":1,"category_id":1,"bbox":[1,"2",3,4],"score":0.5}])",
       "#/0/bbox/1",
       "expected a number"},
      {R"([{"image_id":1.5,"category_id":1,"bbox":[1,2,3,4],"score":0.5}])",
       "#/0/image_id",
       "not an integer"},
      {R"([{"image_id":1,"category_id":1,"bbox":[1,2,3,4]}])", "#/0", "missing 'score'"},
      {"[" + ok + ",", "p.json:1:", "syntax error"},
  };
  for (const BadCase& c : cases) {
    try {
      ParseCocoPredictions(c.text, "p.json", *truth_);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(c.where), std::string::npos) << c.text << "\n" << message;
      EXPECT_NE(message.find(c.what), std::string::npos) << c.text << "\n" << message;
    }
  }
  // file_name instead of image_id: the name lsds convert gives the image.
  const auto by_name = ParseCocoPredictions(
      R"([{"file_name":"000002.png","category_id":2,"bbox":[1,2,3,4],"score":0.5}])",
      "p.json",
      *truth_);
  EXPECT_EQ(by_name.at(0).image_id, 3);
}

TEST_F(EvaluateOnGolden, TheCommandWritesItsOutputsAndExitsByTheThresholds) {
  testing::TempDir out;
  const std::string json = (out / "eval.json").string(), junit = (out / "eval.xml").string();
  const std::string base =
      "evaluate " + C() + " --predictions " + GoldenData("jittered.json").string();
  const testing::CommandResult run =
      testing::RunLsds(base + " -o " + json + " --junit " + junit + " --fail-under AP50=0.1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("Average Precision  (AP) @[ IoU=0.50:0.95 | area=   all"),
            std::string::npos)
      << run.output;
  const nlohmann::json doc = ReadJsonFile(json);
  EXPECT_TRUE(JsonSchema::Get("evaluate.schema.json").Validate(doc).empty());
  EXPECT_EQ(doc["thresholds"][0]["passed"], true);
  EXPECT_NE(ReadFile(junit).find("<testsuites"), std::string::npos);

  // An existing output is not replaced without --force, and not touched.
  const std::string before = ReadFile(json);
  const testing::CommandResult again = testing::RunLsds(base + " -o " + json + " -q");
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_EQ(ReadFile(json), before);

  // A threshold above the metric: exit 1, the failure in the JUnit report.
  const testing::CommandResult fail = testing::RunLsds(base + " -o " + json + " --junit " + junit +
                                                       " --force -q --fail-under AP=0.99");
  EXPECT_EQ(fail.exit_code, 1) << fail.output;
  EXPECT_TRUE(fail.output.empty()) << fail.output;  // -q
  EXPECT_NE(ReadFile(junit).find("<failure"), std::string::npos);
  EXPECT_EQ(ReadJsonFile(json)["thresholds"][0]["passed"], false);

  const testing::CommandResult unknown = testing::RunLsds(base + " --fail-under mAP=0.5");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
}

TEST_F(EvaluateOnGolden, BadPredictionsWriteNothingAndExit2) {
  testing::TempDir out;
  const fs::path bad = out / "bad.json";
  WriteFileAtomic(bad, R"([{"image_id":1,"category_id":1,"bbox":[1,2,3,-4],"score":0.5}])");
  const testing::CommandResult run = testing::RunLsds(
      "evaluate " + C() + " --predictions " + bad.string() + " -o " + (out / "e.json").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("bad.json#/0/bbox/3"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out / "e.json"));
}

TEST_F(EvaluateOnGolden, CoverageNeedsNoPredictions) {
  testing::TempDir out;
  const testing::CommandResult run =
      testing::RunLsds("evaluate " + C() + " --coverage -o " + (out / "cov.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("empty"), std::string::npos) << run.output;
  const nlohmann::json doc = ReadJsonFile(out / "cov.json");
  EXPECT_TRUE(JsonSchema::Get("evaluate.schema.json").Validate(doc).empty());
  EXPECT_FALSE(doc.contains("coco"));
  EXPECT_EQ(testing::RunLsds("evaluate " + C()).exit_code, 2);
}

}  // namespace
}  // namespace lsds::evaluate
