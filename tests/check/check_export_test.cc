// `lsds check-export` end to end. The planted folders are written here, file
// by file; what each consumer does with them is stated from the consumer's
// loader (file and line named at each expectation), not from lsds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "converters/check/registry.h"
#include "libs/collection/schema.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using testing::RunLsds;

void Write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

void WriteImage(const fs::path& path, int width, int height) {
  fs::create_directories(path.parent_path());
  ASSERT_TRUE(cv::imwrite(path.string(), cv::Mat(height, width, CV_8UC3, cv::Scalar(40, 80, 120))));
}

bool Has(const std::string& output, const std::string& text) {
  return output.find(text) != std::string::npos;
}

// Ultralytics: a coordinate above 1.01 (ultralytics/data/utils.py:219) and a
// class >= len(names) (utils.py:223-227, dataset.py:118) drop the image; a
// repeated row is removed (utils.py:228-233).
TEST(CheckExport, YoloPlantedDefectsAreNamedWithFileAndLine) {
  const testing::TempDir dir;
  const fs::path root = dir / "yolo";
  Write(root / "data.yaml", "train: images/train\nval: images/train\nnames:\n  0: car\n  1: bus\n");
  for (const char* stem : {"a", "b", "c", "d"})
    WriteImage(root / "images/train" / (std::string(stem) + ".png"), 64, 48);
  Write(root / "labels/train/a.txt", "0 0.5 0.5 0.2 0.2\n1 1.02 0.5 0.1 0.1\n");
  Write(root / "labels/train/b.txt", "1 0.5 0.5 0.2 0.2\n2 0.5 0.5 0.1 0.1\n");
  Write(root / "labels/train/c.txt", "0 0.3 0.3 0.1 0.1\n0 0.3 0.3 0.1 0.1\n");
  Write(root / "labels/train/d.txt", "1 0.9 0.9 0.2 0.2\n");  // x + w/2 = 1.0: inside
  const testing::CommandResult r = RunLsds("check-export yolo " + root.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(Has(r.output, "labels/train/a.txt:2: ultralytics: ultralytics.coordinate-range: "))
      << r.output;
  EXPECT_TRUE(Has(r.output, "labels/train/b.txt:2: ultralytics: ultralytics.class-range: "))
      << r.output;
  EXPECT_TRUE(Has(r.output, "labels/train/c.txt:2: ultralytics: ultralytics.duplicate-row: "))
      << r.output;
  EXPECT_FALSE(Has(r.output, "d.txt")) << r.output;
  EXPECT_FALSE(Has(r.output, "a.txt:1")) << r.output;
}

// A segment's coordinates are checked through its bounding box (x, y, w, h;
// utils.py:206-209 then 219): a vertex at 1.02 of a polygon spanning
// 0.5..1.02 gives x = 0.76, w = 0.52 and passes; a polygon wholly at
// 1.015..1.03 gives x = 1.0225 and drops the image.
TEST(CheckExport, YoloSegmentsAreCheckedThroughTheirBoundingBox) {
  const testing::TempDir dir;
  const fs::path root = dir / "seg";
  Write(root / "data.yaml", "train: images/train\nval: images/train\nnames: [car]\n");
  WriteImage(root / "images/train/a.png", 32, 32);
  WriteImage(root / "images/train/b.png", 32, 32);
  Write(root / "labels/train/a.txt", "0 0.5 0.5 1.02 0.5 0.8 0.9\n");
  Write(root / "labels/train/b.txt", "0 1.015 0.5 1.03 0.5 1.02 0.9\n");
  const testing::CommandResult r = RunLsds("check-export yolo-seg " + root.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_FALSE(Has(r.output, "a.txt")) << r.output;
  EXPECT_TRUE(Has(r.output, "labels/train/b.txt:1: ultralytics: ultralytics.coordinate-range"))
      << r.output;
}

// The corners of a w x h rectangle centred at (cx, cy), turned by `degrees`.
std::string Corners(double cx, double cy, double w, double h, double degrees) {
  const double a = degrees * M_PI / 180, c = std::cos(a), s = std::sin(a);
  std::string text;
  const double xs[4] = {-w / 2, w / 2, w / 2, -w / 2}, ys[4] = {-h / 2, -h / 2, h / 2, h / 2};
  for (int i = 0; i < 4; ++i) {
    text += std::to_string(cx + c * xs[i] - s * ys[i]) + " " +
            std::to_string(cy + s * xs[i] + c * ys[i]) + " ";
  }
  return text;
}

// DOTA: a box of 1.5 px is skipped by MMRotate (cv2.minAreaRect side < 2,
// mmrotate/core/bbox/transforms.py:347); a 9-token line is skipped by
// Datumaro (dota.py:109) and stops MMRotate (dota.py:106: bbox_info[9]).
TEST(CheckExport, DotaPlantedDefectsAreNamedWithFileAndLine) {
  const testing::TempDir dir;
  const fs::path root = dir / "dota";
  WriteImage(root / "images/P1.png", 64, 64);
  Write(root / "labelTxt/P1.txt",
        Corners(20, 20, 12, 6, 0) + "small-vehicle 0\n" + Corners(40, 40, 10, 1.5, 30) +
            "small-vehicle 0\n" + Corners(30, 10, 8, 4, 0) + "small-vehicle\n");
  const testing::CommandResult r = RunLsds("check-export dota " + root.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(Has(r.output, "labelTxt/P1.txt:2: mmrotate: mmrotate.min-size: ")) << r.output;
  EXPECT_TRUE(Has(r.output, "labelTxt/P1.txt:3: mmrotate: mmrotate.tokens: ")) << r.output;
  EXPECT_TRUE(Has(r.output, "labelTxt/P1.txt:3: datumaro: datumaro.tokens: ")) << r.output;
  EXPECT_TRUE(Has(r.output, "labelTxt/P1.txt:3: dota-devkit: dota-devkit.default-difficult: "))
      << r.output;
  EXPECT_FALSE(Has(r.output, "P1.txt:1:")) << r.output;
  // One consumer only, and its JUnit: the rule broken is a failing test case.
  const testing::CommandResult junit =
      RunLsds("check-export dota " + root.string() + " --consumer datumaro --format junit");
  EXPECT_EQ(junit.exit_code, 1) << junit.output;
  EXPECT_TRUE(Has(junit.output, "name=\"datumaro.tokens\"")) << junit.output;
  EXPECT_TRUE(Has(junit.output, "<failure message=\"1 finding(s): labelTxt/P1.txt:3: "))
      << junit.output;
  EXPECT_FALSE(Has(junit.output, "mmrotate")) << junit.output;
}

// TrackEval: a frame outside 1..seqLength stops the evaluation
// (trackeval/datasets/mot_challenge_2d_box.py:212-222).
TEST(CheckExport, MotFrameZeroIsNamedWithFileAndLine) {
  const testing::TempDir dir;
  const fs::path root = dir / "mot";
  Write(root / "seqmaps/MOT17-train.txt", "name\nSEQ-01\n");
  Write(root / "MOT17-train/SEQ-01/seqinfo.ini",
        "[Sequence]\nname=SEQ-01\nimDir=img1\nframeRate=10\nseqLength=3\nimWidth=64\n"
        "imHeight=48\nimExt=.png\n");
  Write(root / "MOT17-train/SEQ-01/gt/gt.txt",
        "1,1,10,10,5,5,1,1,1.0\n0,1,10,10,5,5,1,1,1.0\n2,1,11,10,5,5,1,1,1.0\n");
  const testing::CommandResult r = RunLsds("check-export mot " + root.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(Has(r.output, "MOT17-train/SEQ-01/gt/gt.txt:2: trackeval: trackeval.frame-range: "))
      << r.output;
  EXPECT_FALSE(Has(r.output, "gt.txt:1:")) << r.output;
  EXPECT_FALSE(Has(r.output, "gt.txt:3:")) << r.output;
}

// TrackEval scores class 1 only and not the zero-marked lines
// (mot_challenge_2d_box.py:389-393), refuses an id twice in one frame
// (_base_dataset.py:316-326) and evaluates only the sequences a seqmap lists
// (mot_challenge_2d_box.py:159-165). Zero-marked lines are the format's own
// ignore flag: reported, never a failure by themselves.
TEST(CheckExport, MotClassesZeroMarksDuplicateIdsAndUnlistedSequences) {
  const testing::TempDir dir;
  const fs::path root = dir / "mot";
  Write(root / "seqmaps/MOT17-train.txt", "name\nS1\n");
  for (const char* seq : {"S1", "S2"}) {
    Write(root / "MOT17-train" / seq / "seqinfo.ini", "[Sequence]\nseqLength=2\n");
    Write(root / "MOT17-train" / seq / "gt/gt.txt",
          "1,1,1,1,5,5,1,3,1\n1,1,2,2,5,5,0,3,1\n2,2,1,1,5,5,1,1,1\n");
  }
  const testing::CommandResult r = RunLsds("check-export mot " + root.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(Has(r.output, "MOT17-train/S1/gt/gt.txt:2: trackeval: trackeval.duplicate-id: "))
      << r.output;
  EXPECT_TRUE(Has(r.output, "MOT17-train/S1/gt/gt.txt:1: trackeval: trackeval.class-scored: 2 "))
      << r.output;
  EXPECT_TRUE(Has(r.output, "MOT17-train/S1/gt/gt.txt:2: trackeval: trackeval.zero-marked: 1 "))
      << r.output;
  EXPECT_TRUE(Has(r.output, "MOT17-train/S2: trackeval: trackeval.unlisted-sequence: "))
      << r.output;
  EXPECT_FALSE(Has(r.output, "S2/gt/gt.txt")) << r.output;
  // A sequence of class-1 lines, one of them zero-marked: nothing lost
  // that the format did not mean to leave out.
  Write(root / "MOT17-train/S1/gt/gt.txt", "1,1,1,1,5,5,1,1,1\n2,1,1,1,5,5,0,1,1\n");
  fs::remove_all(root / "MOT17-train/S2");
  const testing::CommandResult clean = RunLsds("check-export mot " + root.string());
  EXPECT_EQ(clean.exit_code, 0) << clean.output;
  EXPECT_TRUE(Has(clean.output, "trackeval.zero-marked")) << clean.output;
}

// pycocotools: an annotation whose category_id no category has is never
// evaluated (cocoeval.py:81 takes catIds from the categories; coco.py:149
// filters by them). The line is the annotation's own.
TEST(CheckExport, CocoUnknownCategoryIsNamedWithFileAndLine) {
  const testing::TempDir dir;
  const fs::path root = dir / "coco";
  const std::string text =
      "{\n\"images\": [\n{\"id\": 1, \"width\": 10, \"height\": 10, \"file_name\": \"a.png\"}\n],\n"
      "\"categories\": [\n{\"id\": 1, \"name\": \"car\"}\n],\n\"annotations\": [\n"
      "{\"id\": 1, \"image_id\": 1, \"category_id\": 1, \"bbox\": [1, 1, 3, 3], \"area\": 9, "
      "\"iscrowd\": 0},\n"
      "{\"id\": 2, \"image_id\": 1, \"category_id\": 7, \"bbox\": [2, 2, 3, 3], \"area\": 9, "
      "\"iscrowd\": 0}\n]\n}\n";
  Write(root / "annotations/instances_train.json", text);
  // The line of annotation 2, counted here.
  const size_t at = text.find("{\"id\": 2");
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
  const testing::CommandResult r = RunLsds("check-export coco " + root.string() + " --format json");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const nlohmann::json report = nlohmann::json::parse(r.output);
  ASSERT_EQ(report["findings"].size(), 1u) << r.output;
  const nlohmann::json& f = report["findings"][0];
  EXPECT_EQ(f["rule"], "pycocotools.unknown-category");
  EXPECT_EQ(f["file"], "annotations/instances_train.json");
  EXPECT_EQ(f["line"], line);
  EXPECT_EQ(f["severity"], "dropped-box");
  EXPECT_EQ(report["verdict"], "fail");
  EXPECT_TRUE(JsonSchema::Get("check-export-report.schema.json").Validate(report).empty());
}

// Exports of lsds convert load whole: every image and box is kept.
TEST(CheckExport, CleanExportsOfConvertPass) {
  const testing::TempDir dir;
  const fs::path collection = dir / "C";
  const testing::CommandResult synth =
      RunLsds("synth " + collection.string() + " --count 6 --size 96x64");
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  for (const std::string format : {"yolo", "yolo-seg", "coco"}) {
    const fs::path out = dir / format;
    const testing::CommandResult convert = RunLsds("convert " + collection.string() + " --to " +
                                                   format + " --images png -o " + out.string());
    ASSERT_EQ(convert.exit_code, 0) << convert.output;
    const testing::CommandResult r = RunLsds("check-export " + format + " " + out.string());
    EXPECT_EQ(r.exit_code, 0) << format << ": " << r.output;
    EXPECT_TRUE(Has(r.output, "PASS: 0 finding(s)")) << r.output;
  }
}

// Every rule is documented with its severity and names the consumer's source
// file and line; rule ids are unique and start with their consumer's name.
TEST(CheckExport, EveryRuleIsDocumentedWithItsSeverity) {
  std::ifstream in(testing::SourceDir() + "/docs/check-export.md");
  const std::string docs((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(docs.empty());
  std::set<std::string> ids;
  for (const check::Consumer& consumer : check::Consumers()) {
    for (const check::Rule& rule : consumer.rules()) {
      EXPECT_TRUE(ids.insert(rule.id).second) << rule.id;
      EXPECT_EQ(std::string(rule.id).rfind(std::string(consumer.name) + ".", 0), 0u) << rule.id;
      EXPECT_TRUE(Has(
          docs, "| `" + std::string(rule.id) + "` | " + check::SeverityName(rule.severity) + " |"))
          << rule.id;
      EXPECT_TRUE(std::regex_search(rule.source, std::regex(R"(\.(py|pyx):[0-9]+)"))) << rule.id;
    }
  }
}

TEST(CheckExport, BadUsageExitsTwo) {
  const testing::TempDir dir;
  EXPECT_EQ(RunLsds("check-export yolo " + (dir / "missing").string()).exit_code, 2);
  const testing::CommandResult unknown = RunLsds("check-export yollo " + dir.path().string());
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_TRUE(Has(unknown.output, "did you mean 'yolo'")) << unknown.output;
  const testing::CommandResult consumer =
      RunLsds("check-export yolo " + dir.path().string() + " --consumer datumaro");
  EXPECT_EQ(consumer.exit_code, 2);
  EXPECT_TRUE(Has(consumer.output, "does not read yolo")) << consumer.output;
  const testing::CommandResult help = RunLsds("help");
  EXPECT_TRUE(Has(help.output, "check-export")) << help.output;
}

}  // namespace
}  // namespace lsds
