// lsds evaluate --iou-type obb --format dota: the command end to end on DOTA
// task-1 result files, and bad files named at their line (exit 2, nothing
// written).
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "libs/collection/schema.h"
#include "libs/util/atomic_file.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

namespace fs = std::filesystem;

using DotaEvaluate = GoldenCollection;

TEST_F(DotaEvaluate, TheCommandScoresOrientedBoxesAsTheDevkitDoes) {
  testing::TempDir out;
  const std::string json = (out / "eval.json").string();
  const std::string base = "evaluate " + C() + " --predictions " +
                           GoldenData("obb/jittered").string() + " --format dota --iou-type obb";
  const testing::CommandResult run = testing::RunLsds(base + " -o " + json);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("DOTA task 1 (oriented boxes, polygon IoU > 0.5, VOC AP 07"),
            std::string::npos)
      << run.output;
  const nlohmann::json doc = ReadJsonFile(json);
  EXPECT_TRUE(JsonSchema::Get("evaluate.schema.json").Validate(doc).empty());
  EXPECT_EQ(doc["options"]["iou_type"], "obb");
  // The devkit's numbers on the same files (dota_eval_golden_test.cc).
  EXPECT_NEAR(doc["dota"]["mAP"].get<double>(), 0.73407747186183037, 1e-9);
  EXPECT_EQ(doc["dota"]["ap"], "voc07");
  EXPECT_FALSE(doc["coverage"].empty());

  const testing::CommandResult voc12 =
      testing::RunLsds(base + " --ap voc12 -q -o " + (out / "e12.json").string());
  ASSERT_EQ(voc12.exit_code, 0) << voc12.output;
  EXPECT_NEAR(
      ReadJsonFile(out / "e12.json")["dota"]["mAP"].get<double>(), 0.73766475360222405, 1e-9);
}

TEST_F(DotaEvaluate, CocoRulesScoreTheConvertersOwnBoxesOne) {
  // The labels `lsds convert --to dota` writes, turned into task-1 result
  // files (every object, difficult ones too, score 1), scored by COCO's rules
  // with the polygon IoU: every IoU is 1, so every number is 1 (up to COCO's
  // tp / (tp + eps)), and the perfect golden set gives the same.
  testing::TempDir out;
  const testing::CommandResult convert = testing::RunLsds(
      "convert " + C() + " --to dota --images none -q -o " + (out / "dota").string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  std::map<std::string, std::string> results;  // class -> Task1 lines
  int64_t objects = 0;
  for (const auto& entry : fs::recursive_directory_iterator(out / "dota" / "labelTxt")) {
    if (!entry.is_regular_file()) continue;
    std::istringstream lines(ReadTextFile(entry.path()));
    for (std::string line; std::getline(lines, line);) {
      std::istringstream fields(line);
      std::vector<std::string> f;
      for (std::string token; fields >> token;) f.push_back(token);
      if (f.size() < 9) continue;
      std::string corners;
      for (size_t i = 0; i < 8; ++i) corners += " " + f[i];
      results[f[8]] += entry.path().stem().string() + " 1" + corners + "\n";
      ++objects;
    }
  }
  ASSERT_GE(objects, 10);
  fs::create_directories(out / "results");
  for (const auto& [name, text] : results)
    WriteFileAtomic(out / "results" / ("Task1_" + name + ".txt"), text);
  for (const fs::path& predictions : {out / "results", GoldenData("obb/perfect")}) {
    const std::string json = (out / (predictions.filename().string() + ".json")).string();
    const testing::CommandResult run = testing::RunLsds(
        "evaluate " + C() + " --format dota --iou-type obb --ap coco --predictions " +
        predictions.string() + " --fail-under AP=0.99 -o " + json);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("oriented boxes (polygon IoU, COCO's rules)"), std::string::npos)
        << run.output;
    const nlohmann::json doc = ReadJsonFile(json);
    EXPECT_TRUE(JsonSchema::Get("evaluate.schema.json").Validate(doc).empty());
    EXPECT_EQ(doc["options"]["iou_type"], "obb");
    EXPECT_FALSE(doc.contains("dota"));
    for (const char* metric : {"AP", "AP50", "AP75", "AR100"})
      EXPECT_NEAR(doc["coco"][metric].get<double>(), 1, 1e-12) << metric << " " << predictions;
    EXPECT_EQ(doc["counts"]["matched_50"], doc["counts"]["objects"]);
    EXPECT_EQ(doc["counts"]["false_positives_50"], 0);
  }
}

TEST_F(DotaEvaluate, BadResultFilesAreNamedAtTheirLine) {
  struct BadCase {
    std::string file, text;
    std::string where, what;
  };
  const std::string ok = "000001 0.5 1 1 9 1 9 9 1 9\n";
  const BadCase cases[] = {
      {"Task1_plane.txt", ok, "Task1_plane.txt", "'plane' is not a class"},
      {"Task1_box.txt", ok + "000001 0.5 1 1 9 1 9 9 1\n", "Task1_box.txt:2", "got 9"},
      {"Task1_box.txt", "000001  0.5 1 1 9 1 9 9 1 9\n", "Task1_box.txt:1", "got 11"},
      {"Task1_box.txt",
       "999999 0.5 1 1 9 1 9 9 1 9\n",
       "Task1_box.txt:1",
       "'999999' is not an image"},
      {"Task1_box.txt",
       "000001 nan 1 1 9 1 9 9 1 9\n",
       "Task1_box.txt:1",
       "the score is not a finite"},
      {"Task1_box.txt", "000001 0.5 1 1 9 x 9 9 1 9\n", "Task1_box.txt:1", "a corner"},
      {"readme.txt", ok, "", "no Task1_<class>.txt file"},
  };
  for (const BadCase& c : cases) {
    testing::TempDir out;
    fs::create_directories(out / "results");
    WriteFileAtomic(out / "results" / c.file, c.text);
    const testing::CommandResult run =
        testing::RunLsds("evaluate " + C() + " --format dota --iou-type obb -q --predictions " +
                         (out / "results").string() + " -o " + (out / "e.json").string());
    EXPECT_EQ(run.exit_code, 2) << c.text << run.output;
    EXPECT_NE(run.output.find(c.where), std::string::npos) << c.text << run.output;
    EXPECT_NE(run.output.find(c.what), std::string::npos) << c.text << run.output;
    EXPECT_FALSE(fs::exists(out / "e.json"));
  }
  // Oriented boxes come in DOTA files; DOTA files hold oriented boxes.
  const std::string folder = GoldenData("obb/perfect").string();
  EXPECT_EQ(
      testing::RunLsds("evaluate " + C() + " --format dota -q --predictions " + folder).exit_code,
      2);
  // --fail-under reads COCO's numbers, which every obb evaluation computes.
  EXPECT_EQ(testing::RunLsds("evaluate " + C() +
                             " --iou-type obb --fail-under AP=0.99 -q "
                             "--format dota --predictions " +
                             folder)
                .exit_code,
            0);
  // The jittered set's COCO AP (polygon IoU) is 0.273.
  EXPECT_EQ(testing::RunLsds("evaluate " + C() +
                             " --iou-type obb --fail-under AP=0.5 -q "
                             "--format dota --predictions " +
                             GoldenData("obb/jittered").string())
                .exit_code,
            1);
}

}  // namespace
}  // namespace lsds::evaluate
