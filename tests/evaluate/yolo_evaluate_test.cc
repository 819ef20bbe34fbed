// lsds evaluate --format yolo: Ultralytics' prediction files (boxes,
// polygons and oriented boxes) read as the collection's images; the truth converted by
// lsds convert --to yolo / yolo-seg / yolo-obb, given a confidence, scores AP 1; bad files
// are named at their line (exit 2, nothing written).
#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "libs/util/atomic_file.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

namespace fs = std::filesystem;

class YoloEvaluate : public GoldenCollection {
 protected:
  // `lsds convert --to FORMAT` of the golden collection, every label line
  // given the confidence 0.9, as Ultralytics' save_conf writes it.
  static fs::path ConvertedAsPredictions(const fs::path& out, const std::string& format) {
    const testing::CommandResult convert = testing::RunLsds(
        "convert " + C() + " --to " + format + " --images none -q -o " + (out / format).string());
    EXPECT_EQ(convert.exit_code, 0) << convert.output;
    const fs::path predictions = out / (format + "-predictions");
    fs::create_directories(predictions);
    int files = 0;
    for (const auto& entry : fs::directory_iterator(out / format / "labels" / "train")) {
      std::istringstream in(ReadTextFile(entry.path()));
      std::string text;
      for (std::string line; std::getline(in, line);) text += line + " 0.9\n";
      WriteFileAtomic(predictions / entry.path().filename(), text);
      ++files;
    }
    EXPECT_EQ(files, 7);
    return predictions;
  }
};

TEST_F(YoloEvaluate, TheTruthConvertedToYoloScoresOne) {
  testing::TempDir out;
  const fs::path predictions = ConvertedAsPredictions(out / "", "yolo");
  const testing::CommandResult run =
      testing::RunLsds("evaluate " + C() + " --format yolo -q --predictions " +
                       predictions.string() + " -o " + (out / "e.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json doc = ReadJsonFile(out / "e.json");
  EXPECT_EQ(doc["detections"], 82);
  for (const char* metric : {"AP", "AP50", "AP75", "APs", "APm", "APl", "AR100"})
    EXPECT_EQ(doc["coco"][metric], 1.0) << metric;
}

TEST_F(YoloEvaluate, TheTruthConvertedToYoloObbScoresOne) {
  testing::TempDir out;
  const fs::path predictions = ConvertedAsPredictions(out / "", "yolo-obb");
  const testing::CommandResult run =
      testing::RunLsds("evaluate " + C() + " --format yolo --iou-type obb -q --predictions " +
                       predictions.string() + " -o " + (out / "e.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json doc = ReadJsonFile(out / "e.json");
  EXPECT_EQ(doc["detections"], 82);
  // VOC07: eleven times 1/11, 1.0000000000000002 in the devkit too.
  EXPECT_NEAR(doc["dota"]["mAP"].get<double>(), 1.0, 1e-15);
  EXPECT_EQ(doc["dota"]["classes"][0]["true_positives"], doc["dota"]["classes"][0]["objects"]);
}

TEST_F(YoloEvaluate, BadPredictionFilesAreNamedAtTheirLine) {
  struct BadCase {
    std::string file, text;
    std::string where, what;
  };
  const std::string ok = "0 0.5 0.5 0.1 0.1 0.9\n";
  const BadCase cases[] = {
      {"frame7.txt", ok, "frame7.txt", "'frame7' is not an image"},
      {"000001.txt", ok + "0 0.5 0.5 0.1 0.1\n", "000001.txt:2", "no confidence"},
      {"000001.txt", "0 0.5 0.5 0.1\n", "000001.txt:1", "got 4 fields"},
      {"000001.txt", "7 0.5 0.5 0.1 0.1 0.9\n", "000001.txt:1", "class 7 is not a class"},
      {"000001.txt", "0.5 0.5 0.5 0.1 0.1 0.9\n", "000001.txt:1", "not an index"},
      {"000001.txt", "0 0.5 nan 0.1 0.1 0.9\n", "000001.txt:1", "not a finite number: 'nan'"},
      {"000001.txt", "0 0.5 0.5 -0.1 0.1 0.9\n", "000001.txt:1", "negative width"},
      {"notes.md", ok, "", "no <image>.txt file"},
  };
  for (const BadCase& c : cases) {
    testing::TempDir out;
    fs::create_directories(out / "labels");
    WriteFileAtomic(out / "labels" / c.file, c.text);
    const testing::CommandResult run =
        testing::RunLsds("evaluate " + C() + " --format yolo -q --predictions " +
                         (out / "labels").string() + " -o " + (out / "e.json").string());
    EXPECT_EQ(run.exit_code, 2) << c.text << run.output;
    EXPECT_NE(run.output.find(c.where), std::string::npos) << c.text << run.output;
    EXPECT_NE(run.output.find(c.what), std::string::npos) << c.text << run.output;
    EXPECT_FALSE(fs::exists(out / "e.json"));
  }
  // A folder of DOTA result files is no folder of YOLO polygons.
  EXPECT_EQ(testing::RunLsds("evaluate " + C() +
                             " --format yolo --iou-type segm -q "
                             "--predictions " +
                             GoldenData("obb/perfect").string())
                .exit_code,
            2);
}

TEST_F(YoloEvaluate, TheTruthConvertedToYoloSegScoresOneAsMasks) {
  // The polygons lsds convert --to yolo-seg writes, rasterized as Ultralytics
  // rasterizes them, are the collection's masks: every mask IoU is 1.
  testing::TempDir out;
  const fs::path predictions = ConvertedAsPredictions(out / "", "yolo-seg");
  const testing::CommandResult run =
      testing::RunLsds("evaluate " + C() + " --format yolo --iou-type segm --predictions " +
                       predictions.string() + " -o " + (out / "e.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("IoU of masks (iouType segm)"), std::string::npos) << run.output;
  const nlohmann::json doc = ReadJsonFile(out / "e.json");
  EXPECT_EQ(doc["options"]["iou_type"], "segm");
  EXPECT_EQ(doc["detections"], 82);
  for (const char* metric : {"AP", "AP50", "AP75", "APs", "APm", "APl", "AR100"})
    EXPECT_EQ(doc["coco"][metric], 1.0) << metric;
  EXPECT_EQ(doc["counts"]["matched_50"], 82);
  EXPECT_EQ(doc["counts"]["false_positives_50"], 0);

  // One polygon moved by its own width: that object is missed, and the moved
  // mask is a false positive.
  const fs::path moved = out / "moved";
  fs::create_directories(moved);
  for (const auto& entry : fs::directory_iterator(predictions))
    fs::copy_file(entry.path(), moved / entry.path().filename());
  const fs::path first = moved / "000000.txt";
  std::istringstream lines(ReadTextFile(first));
  std::string line, rest;
  std::getline(lines, line);
  for (std::string other; std::getline(lines, other);) rest += other + "\n";
  std::istringstream fields(line);
  std::vector<double> values;
  for (double v; fields >> v;) values.push_back(v);
  double x0 = 1, x1 = 0;
  for (size_t i = 1; i + 1 < values.size(); i += 2)
    x0 = std::min(x0, values[i]), x1 = std::max(x1, values[i]);
  std::ostringstream shifted;
  shifted << values[0];
  for (size_t i = 1; i + 1 < values.size(); ++i)
    shifted << " " << (i % 2 == 1 ? values[i] + (x1 - x0) * 1.5 : values[i]);
  shifted << " 0.9\n";
  fs::remove(first);
  WriteFileAtomic(first, shifted.str() + rest);
  const testing::CommandResult miss =
      testing::RunLsds("evaluate " + C() + " --format yolo --iou-type segm -q --predictions " +
                       moved.string() + " -o " + (out / "m.json").string());
  ASSERT_EQ(miss.exit_code, 0) << miss.output;
  const nlohmann::json missed = ReadJsonFile(out / "m.json");
  EXPECT_EQ(missed["counts"]["matched_50"], 81);
  EXPECT_EQ(missed["counts"]["false_positives_50"], 1);
}

TEST_F(YoloEvaluate, BadPolygonLinesAreNamedAtTheirLine) {
  struct BadCase {
    std::string text, where, what;
  };
  const BadCase cases[] = {
      {"0 0.1 0.1 0.2 0.1 0.2 0.2\n", "000001.txt:1", "an even number of fields), got 7"},
      {"0 0.1 0.1 0.2 0.1 0.9\n", "000001.txt:1", "at least 3 points: got 2"},
      {"0 0.1 0.1 0.2 0.1 0.2 0.2 0.1 0.2 0.9 4\n", "000001.txt:1", "track ids"},
      {"0 0.1 0.1 0.2 0.1 0.2 inf 0.9\n", "000001.txt:1", "not a finite number: 'inf'"},
      {"5 0.1 0.1 0.2 0.1 0.2 0.2 0.9\n", "000001.txt:1", "class 5 is not a class"},
  };
  for (const BadCase& c : cases) {
    testing::TempDir out;
    fs::create_directories(out / "labels");
    WriteFileAtomic(out / "labels" / "000001.txt", c.text);
    const testing::CommandResult run =
        testing::RunLsds("evaluate " + C() + " --format yolo --iou-type segm -q --predictions " +
                         (out / "labels").string() + " -o " + (out / "e.json").string());
    EXPECT_EQ(run.exit_code, 2) << c.text << run.output;
    EXPECT_NE(run.output.find(c.where), std::string::npos) << c.text << run.output;
    EXPECT_NE(run.output.find(c.what), std::string::npos) << c.text << run.output;
    EXPECT_FALSE(fs::exists(out / "e.json"));
  }
}

}  // namespace
}  // namespace lsds::evaluate
