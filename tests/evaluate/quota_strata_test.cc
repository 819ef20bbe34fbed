// The LCAP quotas a collection was generated under are conditions of lsds
// evaluate: a capture with a quota on the target's size is generated and
// converted to COCO; a "model" that finds every object but those of the frames
// in one quota bin has that bin ranked worst, with the counts the collection's
// own records give; coverage counts the collection's frames per bin beside
// the planned ones; --suggest raises that bin's weight in the capture's quota.
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "libs/util/atomic_file.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// One 2 x 2 m target seen from 8 to 60 m: 35 down to 5 pixels across.
const char* const kScene =
    "LSCENE = ONE(W) ONE(T)\n"
    "W = terrain{size:[200,200]}\n"
    "T = object{class:cube,extent:[2,2,1],position:{ON:W,within:[[-1,-1,-10],[1,1,10]]}}\n";
const char* const kCapture =
    "LCAP = ONE(CO) ONE(R) ONE(Q) ONE(CL)\n"
    "CO = camera{csettings:{fov:60,res:[160,120]},targets:[T]}\n"
    "R = path{random:{count:24,x:[-2,2],y:[-2,2],altitude:[8,60],off_nadir:[0,5],yaw:[0,360]}}\n"
    "Q = quota{target:T,quantity:size_px,bins:[4,12,24,40],weights:[1,1,1]}\n"
    "CL = collection{CO:{move:[R]}}\n";
const std::vector<double> kEdges = {4, 12, 24, 40};
const std::vector<std::string> kLabels = {"[4, 12)", "[12, 24)", "[24, 40]"};
constexpr int kMissedBin = 1;  // the model finds nothing in the frames of [12, 24)

// The bin of quota Q each frame of the collection achieved (collection.json's
// own records, docs/format.md "Requirements"); -1: none.
std::map<int64_t, int> AchievedBins(const json& collection) {
  std::map<int64_t, int> bins;
  for (const json& frame : collection["frames"]) {
    int bin = -1;
    for (const json& check : frame["requirements"]["checks"]) {
      if (check["name"] != "Q" || !check.contains("achieved")) continue;
      const double v = check["achieved"].get<double>();
      for (int b = 0; b + 1 < static_cast<int>(kEdges.size()); ++b)
        if (v >= kEdges[b] && (v < kEdges[b + 1] || (b == 2 && v <= kEdges[b + 1]))) bin = b;
    }
    bins[frame["index"].get<int64_t>()] = bin;
  }
  return bins;
}

const json* Named(const json& list, const std::string& name) {
  for (const json& item : list)
    if (item["name"] == name) return &item;
  return nullptr;
}

TEST(EvaluateQuotaStrata, TheQuotaBinAModelMissesIsRankedWorstWithTheCollectionsCounts) {
  testing::TempDir dir;
  const std::string c = (dir / "C").string();
  const testing::CommandResult generate = GenerateFromText(dir.path(), kScene, kCapture);
  ASSERT_EQ(generate.exit_code, 0) << generate.output;
  const testing::CommandResult convert =
      testing::RunLsds("convert " + c + " --to coco --images none -o " + (dir / "coco").string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;

  const json collection = ReadJsonFile(fs::path(c) / "collection.json");
  const std::map<int64_t, int> bin_of_frame = AchievedBins(collection);
  const json coco = ReadJsonFile(dir / "coco" / "annotations" / "instances_train.json");
  std::map<int64_t, int> bin_of_image;
  for (const json& image : coco["images"])
    bin_of_image[image["id"].get<int64_t>()] = bin_of_frame.at(image["lsds"]["frame"]);

  // The model: every object exactly, but none in the frames of kMissedBin.
  std::vector<int64_t> objects(kLabels.size(), 0);
  json predictions = json::array();
  for (const json& a : coco["annotations"]) {
    if (a["iscrowd"] != 0) continue;
    const int bin = bin_of_image.at(a["image_id"].get<int64_t>());
    if (bin >= 0) ++objects[bin];
    if (bin == kMissedBin) continue;
    predictions.push_back({{"image_id", a["image_id"]},
                           {"category_id", a["category_id"]},
                           {"bbox", a["bbox"]},
                           {"score", 0.9}});
  }
  std::vector<int64_t> frames(kLabels.size(), 0);
  int64_t unrecorded = 0;
  for (const auto& [frame, bin] : bin_of_frame) bin >= 0 ? ++frames[bin] : ++unrecorded;
  ASSERT_GT(objects[kMissedBin], 0);
  ASSERT_GT(objects[0] + objects[2], 0);
  WriteFileAtomic(dir / "p.json", predictions.dump());

  const fs::path next = dir / "next.lcap";
  const testing::CommandResult evaluate =
      testing::RunLsds("evaluate " + c + " --predictions " + (dir / "p.json").string() + " -o " +
                       (dir / "e.json").string() + " --junit " + (dir / "e.xml").string() +
                       " --suggest " + next.string());
  ASSERT_EQ(evaluate.exit_code, 0) << evaluate.output;
  EXPECT_NE(evaluate.output.find("quota:Q (LCAP quota: size_px of T"), std::string::npos)
      << evaluate.output;
  EXPECT_NE(ReadFile(dir / "e.xml").find("quota:Q"), std::string::npos);

  const json report = ReadJsonFile(dir / "e.json");
  const json* strata = Named(report["conditions"], "quota:Q");
  ASSERT_NE(strata, nullptr) << report["conditions"].dump();
  EXPECT_EQ((*strata)["level"], "frame");
  const json& worst = (*strata)["strata"][0];
  EXPECT_EQ(worst["label"], kLabels[kMissedBin]);
  EXPECT_EQ(worst["objects"], objects[kMissedBin]);
  EXPECT_EQ(worst["frames"], frames[kMissedBin]);
  EXPECT_EQ(worst["matched_50"], 0);
  EXPECT_EQ(worst["recall_50"], 0.0);
  for (size_t s = 1; s < (*strata)["strata"].size(); ++s) {
    const json& other = (*strata)["strata"][s];
    const auto label = std::find(kLabels.begin(), kLabels.end(), other["label"]);
    ASSERT_NE(label, kLabels.end());
    EXPECT_EQ(other["objects"], objects[label - kLabels.begin()]);
    EXPECT_EQ(other["matched_50"], objects[label - kLabels.begin()]);
  }

  const json* coverage = Named(report["coverage"], "quota:Q");
  ASSERT_NE(coverage, nullptr);
  EXPECT_EQ((*coverage)["unrecorded"], unrecorded);
  const json& planned = collection["provenance"]["requirements"]["quotas"][0]["planned"];
  ASSERT_EQ((*coverage)["cells"].size(), kLabels.size());
  for (size_t b = 0; b < kLabels.size(); ++b) {
    const json& cell = (*coverage)["cells"][b];
    EXPECT_EQ(cell["label"], kLabels[b]);
    EXPECT_EQ(cell["frames"], frames[b]) << b;
    EXPECT_EQ(cell["objects"], objects[b]) << b;
    EXPECT_EQ(cell["planned"], planned[b]) << b;
  }
  // --coverage alone gives the same cells.
  const testing::CommandResult only =
      testing::RunLsds("evaluate " + c + " --coverage -o " + (dir / "cov.json").string());
  ASSERT_EQ(only.exit_code, 0) << only.output;
  EXPECT_EQ(*Named(ReadJsonFile(dir / "cov.json")["coverage"], "quota:Q"), *coverage);

  // --suggest raises the weight of the missed bin in Q itself (no parallel
  // size quota), and lsds plan plans more frames there.
  const std::string lcap = ReadFile(next);
  EXPECT_EQ(lcap.find("SUGGEST_SIZE_PX"), std::string::npos) << lcap;
  EXPECT_NE(lcap.find("# lsds evaluate --suggest: weights raised, worst quota:Q [12, 24)"),
            std::string::npos)
      << lcap;
  const fs::path plan = dir / "plan.json";
  const testing::CommandResult planned_next = testing::RunLsds(
      "plan " + (dir / "s.lscene").string() + " " + next.string() + " -o " + plan.string());
  ASSERT_EQ(planned_next.exit_code, 0) << planned_next.output << "\n" << lcap;
  const json next_planned = ReadJsonFile(plan)["requirements"]["quotas"][0]["planned"];
  EXPECT_GT(next_planned[kMissedBin].get<int64_t>(), planned[kMissedBin].get<int64_t>())
      << next_planned.dump() << " after " << planned.dump() << "\n"
      << lcap;
  for (size_t b = 0; b < kLabels.size(); ++b)
    if (static_cast<int>(b) != kMissedBin)
      EXPECT_GT(next_planned[kMissedBin].get<int64_t>(), next_planned[b].get<int64_t>());
}

}  // namespace
}  // namespace lsds::evaluate
