// The golden collection written once per test suite, and its ground truth as
// lsds evaluate reads it (ReadCollectionTruth: the COCO converter in process).
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "evaluate/ground_truth.h"
#include "tests/build_paths.h"
#include "tests/evaluate/golden_collection.h"
#include "tests/test_util.h"

namespace lsds::evaluate {

// tests/evaluate/data/NAME: the committed prediction sets of the goldens.
inline std::filesystem::path GoldenData(const std::string& name) {
  return std::filesystem::path(testing::SourceDir()) / "tests" / "evaluate" / "data" / name;
}

class GoldenCollection : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir();
    synth::WriteCollection(*dir_ / "c", testing::EvaluateGoldenSpec());
    TruthOptions options;
    options.collection = *dir_ / "c";
    truth_ = new EvaluationTruth(ReadCollectionTruth(options));
  }
  static void TearDownTestSuite() {
    delete truth_;
    delete dir_;
    truth_ = nullptr;
    dir_ = nullptr;
  }
  static std::string C() { return (*dir_ / "c").string(); }

  inline static testing::TempDir* dir_ = nullptr;
  inline static EvaluationTruth* truth_ = nullptr;
};

}  // namespace lsds::evaluate
