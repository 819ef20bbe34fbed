// The golden collection written once per test suite, and its ground truth as
// lsds evaluate reads it (ReadCollectionTruth: the COCO converter in process).
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "evaluate/ground_truth.h"
#include "evaluate/segmentation.h"
#include "libs/util/json_errors.h"
#include "tests/build_paths.h"
#include "tests/evaluate/golden_collection.h"
#include "tests/test_util.h"

namespace lsds::evaluate {

// tests/evaluate/data/NAME: the committed prediction sets of the goldens.
inline std::filesystem::path GoldenData(const std::string& name) {
  return std::filesystem::path(testing::SourceDir()) / "tests" / "evaluate" / "data" / name;
}

// The crowd regions of a committed file (data/crowd_regions.json, or
// data/segm/crowd_regions.json with their masks) added to the ground truth.
inline void AddCrowdRegions(const std::string& name, EvaluationTruth* truth) {
  const std::string file = GoldenData(name).string();
  const nlohmann::json regions = ReadJsonFile(file);
  for (size_t i = 0; i < regions.size(); ++i) {
    const nlohmann::json& a = regions[i];
    GroundTruthBox g;
    g.id = a["id"].get<int64_t>();
    g.image_id = a["image_id"].get<int64_t>();
    g.category_id = a["category_id"].get<int64_t>();
    const nlohmann::json& b = a["bbox"];
    g.bbox = {b[0].get<double>(), b[1].get<double>(), b[2].get<double>(), b[3].get<double>()};
    g.area = a["area"].get<double>();
    g.iscrowd = a["iscrowd"].get<int>() != 0;
    if (truth->coco.iou_type == IouType::kMask) {
      const EvaluationTruth::ImageSize size = truth->image_size.at(g.image_id);
      g.mask = ReadSegmentation(a["segmentation"],
                                size.height,
                                size.width,
                                file,
                                "/" + std::to_string(i) + "/segmentation");
    }
    truth->coco.ground_truth.push_back(g);
  }
}

class GoldenCollection : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir();
    synth::WriteCollection(*dir_ / "c", testing::EvaluateGoldenSpec());
    TruthOptions options;
    options.collection = *dir_ / "c";
    truth_ = new EvaluationTruth(ReadCollectionTruth(options));
    options.masks = true;
    mask_truth_ = new EvaluationTruth(ReadCollectionTruth(options));
  }
  static void TearDownTestSuite() {
    delete truth_;
    delete mask_truth_;
    delete dir_;
    truth_ = nullptr;
    mask_truth_ = nullptr;
    dir_ = nullptr;
  }
  static std::string C() { return (*dir_ / "c").string(); }

  inline static testing::TempDir* dir_ = nullptr;
  inline static EvaluationTruth* truth_ = nullptr;       // boxes (iouType bbox)
  inline static EvaluationTruth* mask_truth_ = nullptr;  // with masks (iouType segm)
};

}  // namespace lsds::evaluate
