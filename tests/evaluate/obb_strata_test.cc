// Oriented boxes broken down by condition: the obb truth is the objects `lsds
// convert --to dota` writes, each with the facts of its object; a "model" that
// misses every turned box under 32 pixels has that size stratum ranked worst,
// and the capture --suggest writes makes lsds plan put most frames there.
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluate/dota_files.h"
#include "evaluate/obb_truth.h"
#include "libs/collection/schema.h"
#include "libs/util/atomic_file.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

namespace fs = std::filesystem;

using ObbStrata = GoldenCollection;

// The label files of `lsds convert --to dota` in `folder`, as the devkit reads
// them, by image stem.
std::vector<DotaObject> ConvertedLabels(const fs::path& folder) {
  std::vector<fs::path> labels;
  for (const auto& entry : fs::recursive_directory_iterator(folder / "labelTxt"))
    if (entry.path().extension() == ".txt") labels.push_back(entry.path());
  std::sort(labels.begin(), labels.end());
  std::vector<DotaObject> objects;
  for (const fs::path& label : labels)
    for (DotaObject& o :
         ParseDotaLabels(ReadTextFile(label), label.string(), label.stem().string()))
      objects.push_back(std::move(o));
  return objects;
}

TEST_F(ObbStrata, TheTruthIsWhatTheConverterWritesWithEachObjectsFacts) {
  testing::TempDir out;
  const testing::CommandResult convert = testing::RunLsds(
      "convert " + C() + " --to dota --images none -q -o " + (out / "dota").string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  const std::vector<DotaObject> written = ConvertedLabels(out / "dota");
  TruthOptions options;
  options.collection = C();
  const ObbTruth obb = ReadObbTruth(options);
  ASSERT_EQ(obb.dota.objects.size(), written.size());
  ASSERT_EQ(obb.truth.coco.ground_truth.size(), written.size());
  ASSERT_EQ(obb.truth.objects.size(), written.size());
  // Never more than the COCO truth: the converter may leave out boxes under --dota-min-size.
  EXPECT_LE(written.size(), truth_->coco.ground_truth.size());
  for (size_t i = 0; i < written.size(); ++i) {
    EXPECT_EQ(obb.dota.objects[i].image, written[i].image);
    EXPECT_EQ(obb.dota.objects[i].class_name, written[i].class_name);
    EXPECT_EQ(obb.dota.objects[i].quad, written[i].quad) << i;
    EXPECT_EQ(obb.dota.objects[i].difficult, written[i].difficult);
    const GroundTruthBox& g = obb.truth.coco.ground_truth[i];
    EXPECT_EQ(g.ignored, written[i].difficult);
    EXPECT_EQ(g.quad, std::vector<double>(written[i].quad.begin(), written[i].quad.end()));
    // Its facts are those of the COCO annotation of the same object.
    const ObjectFacts& facts = obb.truth.objects[i];
    const auto same =
        std::find_if(truth_->objects.begin(), truth_->objects.end(), [&](const auto& o) {
          return o.frame == facts.frame && o.instance_id == facts.instance_id;
        });
    ASSERT_NE(same, truth_->objects.end()) << i;
    EXPECT_EQ(obb.truth.images.At(g.image_id).frame, facts.frame);
    EXPECT_EQ(same->visibility, facts.visibility);
    EXPECT_EQ(same->size_px, facts.size_px);
    EXPECT_EQ(same->in_frame, facts.in_frame);
  }
}

TEST_F(ObbStrata, PerfectOrientedBoxesHaveEveryStratumAtRecallOne) {
  testing::TempDir out;
  const std::string json = (out / "e.json").string();
  const testing::CommandResult run =
      testing::RunLsds("evaluate " + C() + " --format dota --iou-type obb -q --predictions " +
                       GoldenData("obb/perfect").string() + " -o " + json);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json doc = ReadJsonFile(json);
  EXPECT_TRUE(JsonSchema::Get("evaluate.schema.json").Validate(doc).empty());
  EXPECT_NEAR(doc["dota"]["mAP"].get<double>(), 1, 1e-12);
  std::vector<std::string> names;
  int64_t strata_with_objects = 0;
  for (const nlohmann::json& condition : doc["conditions"]) {
    names.push_back(condition["name"]);
    for (const nlohmann::json& s : condition["strata"]) {
      if (s["objects"] == 0) continue;
      ++strata_with_objects;
      EXPECT_EQ(s["recall_50"], 1.0) << condition["name"] << " " << s["label"];
      EXPECT_EQ(s["matched_50"], s["objects"]);
    }
  }
  for (const char* name : {"size_px", "visibility", "in_frame", "class"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  EXPECT_GE(strata_with_objects, 8);
}

// One 4 x 2 m target seen from 9 to 24 m, turned by the camera's yaw: about
// 70 down to 25 pixels across.
const char* const kScene =
    "LSCENE = ONE(W) ONE(T)\n"
    "W = terrain{size:[200,200]}\n"
    "T = object{class:cube,extent:[4,2,1],position:{ON:W,within:[[-1,-1,-10],[1,1,10]]}}\n";
const char* const kCapture =
    "LCAP = ONE(CO) ONE(R) ONE(CL)\n"
    "CO = camera{csettings:{fov:60,res:[160,120]},targets:[T]}\n"
    "R = path{random:{count:30,x:[-2,2],y:[-2,2],altitude:[9,24],off_nadir:[0,5],yaw:[0,360]}}\n"
    "CL = collection{CO:{move:[R]}}\n";
constexpr double kBlindBelow = 32;  // the model finds no turned box smaller (pixels)

bool InBlindStratum(double size) { return size >= 16 && size < kBlindBelow; }

TEST(ObbSuggest, TurnedBoxesMissedUnderASizeRankWorstAndTheNextCaptureAsksForThem) {
  testing::TempDir dir;
  const std::string c = (dir / "C").string();
  const testing::CommandResult generate = GenerateFromText(dir.path(), kScene, kCapture);
  ASSERT_EQ(generate.exit_code, 0) << generate.output;
  const testing::CommandResult convert =
      testing::RunLsds("convert " + c + " --to dota --images none -q -o " + (dir / "d").string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;

  // The model: every oriented box the converter writes whose object is
  // kBlindBelow pixels across and more (size_px, as the strata measure it),
  // exactly; nothing smaller.
  TruthOptions options;
  options.collection = c;
  const ObbTruth obb = ReadObbTruth(options);
  ASSERT_EQ(obb.dota.objects.size(), ConvertedLabels(dir / "d").size());
  std::map<std::string, std::string> results;  // class -> Task1 lines
  int turned = 0, found = 0;
  for (size_t i = 0; i < obb.dota.objects.size(); ++i) {
    const DotaObject& o = obb.dota.objects[i];
    turned += std::abs(o.quad[1] - o.quad[3]) > 1 && std::abs(o.quad[0] - o.quad[2]) > 1;
    if (obb.truth.objects[i].size_px < kBlindBelow) continue;
    std::ostringstream line;
    line << o.image << " 0.9";
    for (double v : o.quad) line << " " << v;
    results[o.class_name] += line.str() + "\n";
    ++found;
  }
  ASSERT_GT(turned, 10);
  ASSERT_GT(found, 0);
  ASSERT_LT(found, static_cast<int>(obb.dota.objects.size()));
  fs::create_directories(dir / "r");
  for (const auto& [name, text] : results)
    WriteFileAtomic(dir / "r" / ("Task1_" + name + ".txt"), text);

  const fs::path next = dir / "next.lcap";
  const testing::CommandResult evaluate = testing::RunLsds(
      "evaluate " + c + " --format dota --iou-type obb --predictions " + (dir / "r").string() +
      " -o " + (dir / "e.json").string() + " --suggest " + next.string());
  ASSERT_EQ(evaluate.exit_code, 0) << evaluate.output;
  const nlohmann::json report = ReadJsonFile(dir / "e.json");
  bool seen = false;
  for (const nlohmann::json& condition : report["conditions"]) {
    if (condition["name"] != "size_px") continue;
    seen = true;
    const nlohmann::json& worst = condition["strata"][0];
    EXPECT_EQ(worst["label"], "[16, 32)") << condition.dump(1);
    EXPECT_GT(worst["objects"].get<int64_t>(), 3);
    EXPECT_EQ(worst["recall_50"], 0.0);
    for (const nlohmann::json& s : condition["strata"])
      if (s["label"] != "[16, 32)" && s["objects"] > 0)
        EXPECT_EQ(s["recall_50"], 1.0) << s["label"];
  }
  EXPECT_TRUE(seen) << report.dump(1);
  const std::string lcap = ReadFile(next);
  EXPECT_NE(lcap.find("quota{target:T,quantity:size_px,bins:[16,32,"), std::string::npos) << lcap;

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
  // The collection's share of turned boxes in the blind stratum, and the plan's.
  const auto blind = [](const std::vector<double>& sizes) {
    return static_cast<double>(std::count_if(sizes.begin(), sizes.end(), InBlindStratum)) /
           static_cast<double>(sizes.size());
  };
  std::vector<double> collection_sizes;
  for (const ObjectFacts& o : obb.truth.objects) collection_sizes.push_back(o.size_px);
  const double share_before = blind(collection_sizes), share_after = blind(plan_sizes);
  EXPECT_GE(share_after, 0.7) << share_before << " -> " << share_after;
  EXPECT_GE(share_after, share_before + 0.25) << share_before << " -> " << share_after;
}

}  // namespace
}  // namespace lsds::evaluate
