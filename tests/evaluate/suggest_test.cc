// lsds evaluate --suggest closes the loop: a "model" that misses every object
// under 8 pixels across has the small strata ranked worst, and the LCAP it
// suggests makes lsds plan (with the collection's own scene) put most frames
// there, counted from the plan's estimates.
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "evaluate/ground_truth.h"
#include "evaluate/suggest.h"
#include "libs/util/atomic_file.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

namespace fs = std::filesystem;

// One 2 x 2 m target seen from 8 to 60 m: 35 down to 5 pixels across.
const char* const kScene =
    "LSCENE = ONE(W) ONE(T)\n"
    "W = terrain{size:[200,200]}\n"
    "T = object{class:cube,extent:[2,2,1],position:{ON:W,within:[[-1,-1,-10],[1,1,10]]}}\n";
const char* const kCapture =
    "LCAP = ONE(CO) ONE(R) ONE(CL)\n"
    "CO = camera{csettings:{fov:60,res:[160,120]},targets:[T]}\n"
    "R = path{random:{count:30,x:[-2,2],y:[-2,2],altitude:[8,60],off_nadir:[0,5],yaw:[0,360]}}\n"
    "CL = collection{CO:{move:[R]}}\n";
constexpr double kBlindBelow = 8;  // the model finds nothing smaller (pixels, larger side)

int CountSmall(const std::vector<double>& sizes) {
  return static_cast<int>(
      std::count_if(sizes.begin(), sizes.end(), [](double s) { return s < kBlindBelow; }));
}

TEST(EvaluateSuggest, TheNextCaptureAsksForTheStrataTheModelMissed) {
  testing::TempDir dir;
  const std::string c = (dir / "C").string();
  const testing::CommandResult generate = GenerateFromText(dir.path(), kScene, kCapture);
  ASSERT_EQ(generate.exit_code, 0) << generate.output;

  // The model: every object of kBlindBelow pixels and more, exactly; nothing smaller.
  TruthOptions options;
  options.collection = c;
  const EvaluationTruth truth = ReadCollectionTruth(options);
  nlohmann::json predictions = nlohmann::json::array();
  std::vector<double> collection_sizes;
  for (const GroundTruthBox& g : truth.coco.ground_truth) {
    collection_sizes.push_back(std::max(g.bbox.w, g.bbox.h));
    if (collection_sizes.back() < kBlindBelow) continue;
    predictions.push_back({{"image_id", g.image_id},
                           {"category_id", g.category_id},
                           {"bbox", {g.bbox.x, g.bbox.y, g.bbox.w, g.bbox.h}},
                           {"score", 0.9}});
  }
  const int small_in_collection = CountSmall(collection_sizes);
  ASSERT_GT(small_in_collection, 0);
  ASSERT_LT(small_in_collection, static_cast<int>(collection_sizes.size()));
  WriteFileAtomic(dir / "p.json", predictions.dump());

  const fs::path next = dir / "next.lcap";
  const testing::CommandResult evaluate =
      testing::RunLsds("evaluate " + c + " --predictions " + (dir / "p.json").string() + " -o " +
                       (dir / "e.json").string() + " --suggest " + next.string());
  ASSERT_EQ(evaluate.exit_code, 0) << evaluate.output;
  const nlohmann::json report = ReadJsonFile(dir / "e.json");
  for (const nlohmann::json& condition : report["conditions"]) {
    if (condition["name"] != "size_px") continue;
    EXPECT_EQ(condition["strata"][0]["label"], "[0, 8)");
    EXPECT_EQ(condition["strata"][0]["recall_50"], 0.0);
  }
  const std::string lcap = ReadFile(next);
  EXPECT_NE(lcap.find("quota{target:T,quantity:size_px,bins:[0,8,"), std::string::npos) << lcap;

  // lsds plan accepts it with the collection's scene; its frames concentrate
  // where the model was blind.
  const fs::path plan = dir / "plan.json";
  const testing::CommandResult planned = testing::RunLsds(
      "plan " + (dir / "s.lscene").string() + " " + next.string() + " -o " + plan.string());
  ASSERT_EQ(planned.exit_code, 0) << planned.output << "\n" << lcap;
  std::vector<double> plan_sizes;
  const nlohmann::json plan_json = ReadJsonFile(plan);
  for (const nlohmann::json& frame : plan_json["frames"]) {
    for (const nlohmann::json& check : frame["requirements"]["checks"])
      if (check["quantity"] == "size_px" && check.contains("estimate"))
        plan_sizes.push_back(check["estimate"].get<double>());
  }
  ASSERT_EQ(plan_sizes.size(), 30u);
  const double share_before = static_cast<double>(small_in_collection) / collection_sizes.size();
  const double share_after = static_cast<double>(CountSmall(plan_sizes)) / plan_sizes.size();
  EXPECT_GE(share_after, 0.7);
  EXPECT_GE(share_after, share_before + 0.25) << share_before << " -> " << share_after;
}

TEST(EvaluateSuggest, ACollectionWithoutACaptureIsRefused) {
  testing::TempDir dir;
  synth::WriteCollection(dir / "c", testing::EvaluateGoldenSpec());
  const testing::CommandResult run = testing::RunLsds(
      "evaluate " + (dir / "c").string() + " --predictions " + GoldenData("perfect.json").string() +
      " --suggest " + (dir / "n.lcap").string() + " -q");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("provenance.capture_source"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir / "n.lcap"));
  const testing::CommandResult coverage = testing::RunLsds(
      "evaluate " + (dir / "c").string() + " --coverage --suggest " + (dir / "n.lcap").string());
  EXPECT_EQ(coverage.exit_code, 2) << coverage.output;
}

// A capture's own quotas are reweighted in place, whichever way their shares
// are written: a class quota's `classes:{name:share}`, its `classes:[...]`
// with no weights, a numeric quota without weights.
TEST(EvaluateSuggest, TheCapturesQuotasGetTheirWorstBinsWeightRaisedInPlace) {
  EvaluationTruth truth;
  truth.capture_source =
      "LCAP = ONE(CO) ONE(KIND) ONE(PAIR) ONE(SUN)\n"
      "KIND = quota{target:V,quantity:class,classes:{car:2,truck:1}}\n"
      "  PAIR = quota{quantity:class,classes:[car,truck]}\n"
      "SUN = quota{quantity:sun_elevation,\n            bins:[10,45,80]\n}\n";
  truth.quotas = nlohmann::json::parse(R"([
      {"name": "KIND", "target": "V", "quantity": "class", "classes": ["car", "truck"],
       "class_ids": [1, 2], "weights": [0.6666666666666666, 0.3333333333333333], "planned": [20, 10]},
      {"name": "PAIR", "quantity": "class", "classes": ["car", "truck"], "class_ids": [1, 2],
       "weights": [0.5, 0.5], "planned": [15, 15]},
      {"name": "SUN", "quantity": "sun_elevation", "bins": [10, 45, 80], "weights": [0.5, 0.5],
       "planned": [15, 15]}])");
  const std::vector<ConditionBins> conditions = BinConditions(truth);
  EvaluationReport report;
  for (const ConditionBins& c : conditions) {
    if (c.quota < 0) continue;
    ConditionMetrics m{c.name, c.description, c.level, {}};
    // The second bin: recall 0.2 of 10 objects; the first: 1 of 10.
    for (const auto& [bin, matched] : {std::pair{1, 2}, std::pair{0, 10}}) {
      StratumMetrics s;
      s.label = c.bins[bin];
      s.objects = 10;
      s.matched_50 = matched;
      s.recall_50 = matched / 10.0;
      m.strata.push_back(s);
    }
    report.strata.push_back(m);
  }
  ASSERT_EQ(report.strata.size(), 3u);
  const Suggestion suggestion = SuggestCapture(truth, conditions, report);
  EXPECT_EQ(suggestion.quotas, (std::vector<std::string>{"KIND", "PAIR", "SUN"}));
  const std::string& lcap = suggestion.lcap;
  // KIND: 2/3 * 0.05 and 1/3 * 0.8, normalised: 0.111 and 0.889.
  EXPECT_NE(lcap.find("KIND = quota{target:V,quantity:class,classes:{car:0.111,truck:0.889}}"),
            std::string::npos)
      << lcap;
  EXPECT_NE(lcap.find("  PAIR = quota{quantity:class,classes:[car,truck],weights:[0.0588,0.941]}"),
            std::string::npos)
      << lcap;
  EXPECT_NE(lcap.find("SUN = quota{quantity:sun_elevation,\n            bins:[10,45,80],weights:"
                      "[0.0588,0.941]}"),
            std::string::npos)
      << lcap;
  EXPECT_NE(
      lcap.find("# lsds evaluate --suggest: weights raised, worst quota:PAIR truck: recall@.5 "
                "0.2 of 10 objects\n  PAIR ="),
      std::string::npos)
      << lcap;
  EXPECT_EQ(lcap.find("LCAP = ONE(CO) ONE(KIND) ONE(PAIR) ONE(SUN)\n"), 0u) << lcap;
}

}  // namespace
}  // namespace lsds::evaluate
