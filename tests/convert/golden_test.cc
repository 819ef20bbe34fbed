// Golden files: the exact output of every format on a tiny collection,
// committed under golden/. Regenerate (after checking the diff!) with
// LSDS_UPDATE_GOLDEN=1 ctest -R convert_golden.
#include <cstdlib>

#include <gtest/gtest.h>

#include "tests/build_paths.h"
#include "tests/convert/convert_test_util.h"

namespace lsds::testing {
namespace {

// 16x12 pixels, three frames of a nadir camera at 8 m over a box and a crate
// (partly out of view in frame 1) and the ground; frame 2 sees no object.
synth::Spec TinySpec() {
  synth::Spec spec = synth::DefaultSpec();
  spec.width = 16;
  spec.height = 12;
  spec.layers = {"rgb", "classid", "instanceid", "depth"};
  spec.boxes.resize(2);
  spec.boxes[1].center = {2.5, 1.0, 0.5};
  spec.boxes[1].class_id = 3;  // a crate
  // The third frame sees only the ground: its label file must exist and be
  // empty.
  spec.cam_from_world = {synth::NadirCamFromWorld({0.0, 0.0, 8.0}),
                         synth::NadirCamFromWorld({-3.0, 0.0, 8.0}),
                         synth::NadirCamFromWorld({100.0, 0.0, 8.0})};
  return spec;
}

std::vector<fs::path> FilesUnder(const fs::path& root) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.is_regular_file()) files.push_back(fs::relative(entry.path(), root));
  }
  std::sort(files.begin(), files.end());
  return files;
}

struct Case {
  std::string name;
  std::vector<std::string> formats;
  std::string segmentation = "rle";
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class GoldenTest : public ::testing::TestWithParam<Case> {};

TEST_P(GoldenTest, ExactFiles) {
  const Case& c = GetParam();
  TempDir dir;
  synth::WriteCollection(dir.path() / "collection", TinySpec());
  const fs::path out = dir.path() / "out";
  convert::ConvertOptions options = Options(dir.path() / "collection", out, c.formats);
  options.segmentation = c.segmentation;
  options.split = "train=0.5,val=0.5";
  convert::Convert(options);
  // data.yaml must not name its own absolute folder (it stays valid when the
  // dataset is moved).
  if (fs::exists(out / "data.yaml")) {
    const std::string path = fs::absolute(out).lexically_normal().string();
    EXPECT_EQ(ReadText(out / "data.yaml").find(path), std::string::npos);
  }
  const fs::path golden =
      fs::path(::lsds::testing::SourceDir()) / "tests" / "convert" / "golden" / c.name;
  if (std::getenv("LSDS_UPDATE_GOLDEN") != nullptr) {
    fs::remove_all(golden);
    fs::create_directories(golden.parent_path());
    fs::copy(out, golden, fs::copy_options::recursive);
    GTEST_SKIP() << "golden files written to " << golden;
  }
  ASSERT_TRUE(fs::is_directory(golden)) << golden << " missing: run with LSDS_UPDATE_GOLDEN=1";
  ASSERT_EQ(FilesUnder(out), FilesUnder(golden));
  for (const fs::path& file : FilesUnder(golden)) {
    EXPECT_EQ(ReadText(out / file), ReadText(golden / file))
        << "differs from the golden file " << golden / file;
  }
}

INSTANTIATE_TEST_SUITE_P(Formats,
                         GoldenTest,
                         ::testing::Values(Case{"yolo", {"yolo"}},
                                           Case{"yolo-seg", {"yolo-seg"}},
                                           Case{"yolo-obb", {"yolo-obb"}},
                                           Case{"dota", {"dota"}},
                                           Case{"coco", {"coco"}},
                                           Case{"coco-polygon", {"coco"}, "polygon"},
                                           Case{"cvat", {"cvat"}},
                                           Case{"cvat-video", {"cvat-video"}},
                                           Case{"mot", {"mot"}},
                                           Case{"visdrone", {"visdrone"}},
                                           Case{"visdrone-vid", {"visdrone-vid"}}),
                         [](const auto& info) {
                           std::string name = info.param.name;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace lsds::testing
