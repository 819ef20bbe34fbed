// lsds evaluate --iou-type segm: the command end to end on mask predictions,
// and bad masks named at their entry (exit 2, nothing written).
#include <string>

#include <gtest/gtest.h>

#include "evaluate/predictions.h"
#include "libs/collection/schema.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

namespace fs = std::filesystem;

using MaskEvaluate = GoldenCollection;

TEST_F(MaskEvaluate, TheCommandScoresMasksAsPycocotoolsDoes) {
  testing::TempDir out;
  const std::string json = (out / "eval.json").string();
  const testing::CommandResult run =
      testing::RunLsds("evaluate " + C() + " --predictions " +
                       GoldenData("segm/jittered.json").string() + " --iou-type segm -o " + json);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("IoU of masks (iouType segm)"), std::string::npos) << run.output;
  const nlohmann::json doc = ReadJsonFile(json);
  EXPECT_TRUE(JsonSchema::Get("evaluate.schema.json").Validate(doc).empty());
  EXPECT_EQ(doc["options"]["iou_type"], "segm");
  // pycocotools' COCOeval(iouType="segm") on the same file (mask_eval_golden_test.cc).
  EXPECT_NEAR(doc["coco"]["AP"].get<double>(), 0.23476296224709386, 1e-9);
  EXPECT_NEAR(doc["coco"]["AP50"].get<double>(), 0.5050558541206781, 1e-9);
  EXPECT_FALSE(doc["conditions"].empty());

  // The same file as boxes: the masks' own boxes (no bbox given) score otherwise.
  const testing::CommandResult boxes = testing::RunLsds(
      "evaluate " + C() + " --predictions " + GoldenData("segm/jittered.json").string() +
      " --iou-type bbox -q -o " + (out / "boxes.json").string());
  ASSERT_EQ(boxes.exit_code, 2) << boxes.output;  // a box result file needs its bbox
  EXPECT_NE(boxes.output.find("jittered.json#/0"), std::string::npos) << boxes.output;
  EXPECT_NE(boxes.output.find("missing 'bbox'"), std::string::npos) << boxes.output;
}

TEST_F(MaskEvaluate, BadMasksAreNamedAtTheirEntry) {
  const std::string head = R"({"image_id":1,"category_id":1,"score":0.5,"segmentation":)";
  struct BadCase {
    std::string segmentation;
    std::string where, what;
  };
  const BadCase cases[] = {
      {R"({"size":[480,640],"counts":"05"})", "#/0/segmentation/size", "the image is [192,256]"},
      {R"({"size":[192,256],"counts":"0 5"})", "#/0/segmentation/counts", "rleFrString"},
      {R"({"size":[192,256],"counts":[10,5]})", "#/0/segmentation/counts", "cover 15 pixels"},
      {R"({"size":[192,256],"counts":[10,-5]})", "#/0/segmentation/counts/1", "run length"},
      {R"({"size":[192,256]})", "#/0/segmentation", "missing 'counts'"},
      {R"([[1,2,3,4]])", "#/0/segmentation/0", "three points"},
      {R"([[1,2,3,4,5,NaN]])", "#/0/segmentation/0/5", "finite"},
      {R"(7)", "#/0/segmentation", "expected a COCO segmentation"},
  };
  for (const BadCase& c : cases) {
    const std::string text = "[" + head + c.segmentation + "}]";
    try {
      ParseCocoPredictions(text, "p.json", *mask_truth_);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(c.where), std::string::npos) << text << "\n" << message;
      EXPECT_NE(message.find(c.what), std::string::npos) << text << "\n" << message;
    }
  }
  // COCO.loadRes's box branch: the first entry has a box, so every entry needs one.
  const std::string rle = R"({"size":[192,256],"counts":[49152]})";
  try {
    ParseCocoPredictions(
        "[" + head + rle + R"(,"bbox":[0,0,1,1]},)" + head + rle + "}]", "p.json", *mask_truth_);
    ADD_FAILURE() << "a second entry without bbox was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("p.json#/1"), std::string::npos) << e.what();
  }
  // Without boxes the area is the mask's and the box the mask's tight one.
  const auto read = ParseCocoPredictions(
      "[" + head + R"({"size":[192,256],"counts":[400,3,189,3,48557]}}])", "p.json", *mask_truth_);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].Area(), 6);
  EXPECT_EQ(read[0].bbox.x, 2);  // 400 = 2 * 192 + 16
  EXPECT_EQ(read[0].bbox.y, 16);
  EXPECT_EQ(read[0].bbox.w, 2);
  EXPECT_EQ(read[0].bbox.h, 3);
}

TEST_F(MaskEvaluate, ABadMaskFileWritesNothingAndExits2) {
  testing::TempDir out;
  const fs::path bad = out / "bad.json";
  WriteFileAtomic(
      bad,
      R"([{"image_id":2,"category_id":1,"score":0.5,"segmentation":{"size":[192,256],"counts":"0h"}}])");
  const testing::CommandResult run =
      testing::RunLsds("evaluate " + C() + " --predictions " + bad.string() +
                       " --iou-type segm -o " + (out / "e.json").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("bad.json#/0/segmentation/counts"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out / "e.json"));
  // Coverage compares nothing: no IoU type.
  EXPECT_EQ(testing::RunLsds("evaluate " + C() + " --coverage --iou-type segm").exit_code, 2);
}

}  // namespace
}  // namespace lsds::evaluate
