// lsds evaluate --format yolo: Ultralytics' prediction files (boxes and
// oriented boxes) read as the collection's images; the truth converted by
// lsds convert --to yolo / yolo-obb, given a confidence, scores AP 1; bad files
// are named at their line (exit 2, nothing written).
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
  // YOLO files hold boxes or oriented boxes, not COCO masks.
  EXPECT_EQ(testing::RunLsds("evaluate " + C() +
                             " --format yolo --iou-type segm -q "
                             "--predictions " +
                             GoldenData("obb/perfect").string())
                .exit_code,
            2);
}

}  // namespace
}  // namespace lsds::evaluate
