// lsds validate as a library: the good synthetic collection passes clean, and
// every corruption of the corpus is reported at its specific check id and
// location.
#include <unistd.h>

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/exr/flat_image.h"
#include "libs/geometry/camera.h"
#include "tests/build_paths.h"
#include "tests/validate/corruptions.h"
#include "validators/camera_checks.h"
#include "validators/checks.h"
#include "validators/report_writers.h"
#include "validators/validate.h"

namespace lsds::validate {
namespace {

namespace fs = std::filesystem;

fs::path TestRoot() {
  static const fs::path root =
      fs::temp_directory_path() / ("lsds_validate_test_" + std::to_string(getpid()));
  return root;
}

class ValidateTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(TestRoot());
    corpus::WriteGoodCollection(TestRoot() / "good");
  }
  static void TearDownTestSuite() { fs::remove_all(TestRoot()); }
  static fs::path Good() { return TestRoot() / "good"; }
  static fs::path Corrupted(const std::string& name, corpus::Expected* expected) {
    const fs::path target = TestRoot() / name;
    fs::remove_all(target);
    corpus::CopyCollection(Good(), target);
    *expected = corpus::FindCorruption(name).apply(target);
    return target;
  }
};

std::string Dump(const Report& report) { return ReportToText(report, Severity::kInfo, 10); }

TEST_F(ValidateTest, GoodCollectionPassesClean) {
  const Report report = ValidateCollection(Good());
  EXPECT_EQ(report.Count(Severity::kError), 0) << Dump(report);
  EXPECT_EQ(report.Count(Severity::kWarning), 0) << Dump(report);
  EXPECT_EQ(report.Count(Severity::kInfo), 0) << Dump(report);
  EXPECT_EQ(report.frames, 4);
  EXPECT_EQ(report.files_decoded,
            4 * 9);  // every layer of every frame, each once
  EXPECT_FALSE(report.Fails(Severity::kWarning));
  ASSERT_TRUE(report.statistics().count("cross.worldpos-depth.error"));
  EXPECT_LT(report.statistics().at("cross.worldpos-depth.error").max, 1e-3);
  ASSERT_TRUE(report.statistics().count("camera.reprojection_rms_px"));
  EXPECT_LT(report.statistics().at("camera.reprojection_rms_px").max, 0.01);
  EXPECT_EQ(report.statistics().at("cross.metadata-pose.metadata.json.position_error").max, 0.0);
}

// A collection written before format 1.1 (no shots, no scene state or new
// object fields, 0.5 motion on the first frame) stays valid: readers keep
// every 1.x, and checks that need 1.1 fields are skipped.
TEST_F(ValidateTest, Format10CollectionStillValidates) {
  const fs::path old = TestRoot() / "format-1.0";
  fs::remove_all(old);
  corpus::CopyCollection(Good(), old);
  nlohmann::json collection;
  {
    std::ifstream in(old / "collection.json");
    collection = nlohmann::json::parse(in);
  }
  collection["format_version"] = "1.0";
  for (auto& frame : collection["frames"]) {
    ASSERT_TRUE(frame.contains("shot"));
    frame.erase("shot");
    frame.erase("scene");
    for (auto& object : frame["objects"])
      for (const char* key : {"asset",
                              "material",
                              "transmittance",
                              "changes",
                              "bbox_oriented",
                              "bbox_oriented_projected"})
        object.erase(key);
  }
  std::ofstream(old / "collection.json") << collection.dump();
  nlohmann::json metadata;
  {
    std::ifstream in(old / "metadata.json");
    metadata = nlohmann::json::parse(in);
  }
  metadata["format_version"] = "1.0";
  std::ofstream(old / "metadata.json") << metadata.dump();
  // 1.0 wrote "no motion" (0.5) on a sequence's first frame.
  const fs::path motion = old / collection["frames"][0]["files"]["motion"];
  exr::FlatImage image = exr::ReadFlatExr(motion, {"X", "Y"});
  for (const char* c : {"X", "Y"})
    for (float& v : image.Get(c).floats) v = 0.5f;
  exr::WriteOptions options;
  options.compression = exr::Compression::kZip;
  exr::WriteFlatExr(motion, image, options);
  const Report report = ValidateCollection(old);
  EXPECT_EQ(report.Count(Severity::kError), 0) << Dump(report);
  EXPECT_EQ(report.Count(Severity::kWarning), 0) << Dump(report);
  EXPECT_EQ(report.frames, 4);
}

class CorpusTest : public ValidateTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(CorpusTest, ReportsCheckAndLocation) {
  corpus::Expected expected;
  const fs::path root = Corrupted(GetParam(), &expected);
  const Report report = ValidateCollection(root);
  const std::vector<Finding> findings = report.Examples(expected.check);
  ASSERT_FALSE(findings.empty()) << "no " << expected.check << " finding\n" << Dump(report);
  bool found = false;
  for (const Finding& f : findings) {
    EXPECT_EQ(f.check_id, expected.check);
    if (f.location.file != expected.file) continue;
    if (expected.frame && f.location.frame != expected.frame) continue;
    if (!expected.json_pointer.empty() && f.location.json_pointer != expected.json_pointer)
      continue;
    if (expected.pixel_x &&
        (f.location.pixel_x != expected.pixel_x || f.location.pixel_y != expected.pixel_y)) {
      continue;
    }
    found = true;
  }
  std::string want = expected.file +
                     (expected.frame ? " frame " + std::to_string(*expected.frame) : "") +
                     (expected.json_pointer.empty() ? "" : " #" + expected.json_pointer) +
                     (expected.pixel_x ? " pixel (" + std::to_string(*expected.pixel_x) + ", " +
                                             std::to_string(*expected.pixel_y) + ")"
                                       : "");
  EXPECT_TRUE(found) << expected.check << " not reported at " << want << "\n" << Dump(report);
  // Statistics (info) are reported but fail nothing at the warning level.
  EXPECT_TRUE(report.Fails(GetCheck(expected.check).severity));
}

std::vector<std::string> CorruptionNames() {
  std::vector<std::string> names;
  for (const corpus::Corruption& c : corpus::Corruptions()) names.push_back(c.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Corpus,
                         CorpusTest,
                         ::testing::ValuesIn(CorruptionNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& ch : name) {
                             if (!isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           }
                           return name;
                         });

TEST_F(ValidateTest, CorpusCoversEveryCheck) {
  std::set<std::string> covered;
  for (const corpus::Corruption& c : corpus::Corruptions()) {
    corpus::Expected e;
    const fs::path root = Corrupted(c.name, &e);
    covered.insert(e.check);
    fs::remove_all(root);
  }
  for (const CheckInfo& check : AllChecks()) {
    EXPECT_TRUE(covered.count(check.id)) << check.id << " has no corruption in the corpus";
  }
}

TEST_F(ValidateTest, DeclaredPerturbedMetadataIsAStatisticNotAFinding) {
  corpus::Expected expected;
  const fs::path root = Corrupted("metadata-pose", &expected);  // frame 2 off by 0.5 m
  {
    std::ifstream in(root / "collection.json");
    nlohmann::json j = nlohmann::json::parse(in);
    j["metadata"][0]["perturbed"] = true;
    std::ofstream(root / "collection.json") << j.dump(1);
  }
  const Report report = ValidateCollection(root);
  EXPECT_EQ(report.CountOf("cross.metadata-pose"), 0) << Dump(report);
  const Statistic& position =
      report.statistics().at("cross.metadata-pose.metadata.json.position_error");
  EXPECT_NEAR(position.max, 0.5, 1e-9);
  EXPECT_EQ(position.count, 4);
}

TEST_F(ValidateTest, CheckSelectionSkipsOtherChecks) {
  corpus::Expected expected;
  const fs::path root = Corrupted("nan-depth", &expected);
  ValidateOptions options;
  options.checks = CheckSelection::Parse("schema,structure");
  const Report report = ValidateCollection(root, options);
  EXPECT_EQ(report.CountOf("layer.depth-finite"), 0);
  EXPECT_EQ(report.files_decoded,
            0);  // nothing decoded when no layer check is selected
  EXPECT_FALSE(report.Fails(Severity::kWarning)) << Dump(report);
  options.checks = CheckSelection::Parse("layer.depth-finite");
  EXPECT_EQ(ValidateCollection(root, options).CountOf("layer.depth-finite"), 1);
}

TEST_F(ValidateTest, SingleThreadGivesTheSameReport) {
  corpus::Expected expected;
  const fs::path root = Corrupted("non-unit-normals", &expected);
  ValidateOptions options;
  options.jobs = 1;
  options.batch_size = 1;
  const Report report = ValidateCollection(root, options);
  EXPECT_EQ(report.CountOf("layer.normal-unit"), 1);
  EXPECT_EQ(report.Count(Severity::kError), 1) << Dump(report);
}

TEST(ValidateInput, NotACollectionThrows) {
  EXPECT_THROW(ValidateCollection("/nonexistent/folder"), Error);
  EXPECT_THROW(ValidateCollection(fs::temp_directory_path()), Error);
}

TEST(CheckSelectionTest, GroupsAndSuggestions) {
  const CheckSelection layer = CheckSelection::Parse("layer");
  EXPECT_TRUE(layer.Has("layer.depth-finite"));
  EXPECT_FALSE(layer.Has("schema"));
  EXPECT_TRUE(CheckSelection::Parse("cross.*, schema").Has("cross.bbox-tight"));
  EXPECT_EQ(CheckSelection::Parse("all").ids().size(), AllChecks().size());
  try {
    CheckSelection::Parse("layer.depth-finit");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'layer.depth-finite'"), std::string::npos)
        << e.what();
  }
}

TEST(DocsTest, DocsListEveryCheck) {
  std::ifstream in(::lsds::testing::SourceDir() + "/docs/validate.md");
  ASSERT_TRUE(in.good());
  std::stringstream text;
  text << in.rdbuf();
  for (const CheckInfo& check : AllChecks()) {
    EXPECT_NE(text.str().find("| `" + check.id + "` | " + SeverityName(check.severity) + " |"),
              std::string::npos)
        << check.id << " is not in docs/validate.md's table";
  }
}

TEST(ReportTest, KeepsCountsButBoundedExamples) {
  Report report(3);
  for (int k = 9; k >= 0; --k) {
    Finding f;
    f.check_id = "layer.depth-finite";
    f.location.frame = k;
    report.Add(f);
  }
  EXPECT_EQ(report.CountOf("layer.depth-finite"), 10);
  const auto examples = report.Examples("layer.depth-finite");
  ASSERT_EQ(examples.size(), 3u);
  EXPECT_EQ(*examples[0].location.frame, 0);  // the earliest frames are kept
  EXPECT_EQ(*examples[2].location.frame, 2);
}

TEST(CameraSolveTest, RecoversFocalLengthFromWrongStart) {
  const PinholeCamera truth = PinholeCamera::FromHorizontalFov(640, 480, 60);
  std::vector<Eigen::Vector2d> pixels;
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d in_cam((k % 20 - 10) * 0.7, (k / 20 - 5) * 0.6, 15 + (k % 7));
    pixels.push_back(truth.ImageFromCam(in_cam));
    points.push_back(in_cam);  // cam_from_world = identity
  }
  const PinholeCamera wrong = PinholeCamera::FromHorizontalFov(640, 480, 70);
  CameraSolution initial;
  initial.fx = wrong.fx, initial.fy = wrong.fy, initial.cx = wrong.cx, initial.cy = wrong.cy;
  const CameraSolution solved = SolveCamera(pixels, points, initial, /*solve_pose=*/true);
  ASSERT_TRUE(solved.solved);
  EXPECT_NEAR(solved.fx, truth.fx, 1e-3 * truth.fx);
  EXPECT_NEAR(solved.fy, truth.fy, 1e-3 * truth.fy);
  EXPECT_LT(solved.rms_px, 1e-3);
}

}  // namespace
}  // namespace lsds::validate
