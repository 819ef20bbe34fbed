#include "tests/import/import_checks.h"

#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/collection/collection_reader.h"
#include "libs/util/strings.h"
#include "tests/convert/reference_decoders.h"
#include "tests/test_util.h"

namespace lsds::testing {

namespace fs = std::filesystem;
using nlohmann::json;

synth::Spec ObliqueImportSpec() {
  synth::Spec spec = synth::DefaultSpec();
  spec.samples_per_axis = 1;
  const Rigid3d look = LookAt({-14, -9, 6}, {0, 0, 1});
  const Eigen::Quaterniond roll(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  spec.cam_from_world.push_back(Rigid3d(roll, Eigen::Vector3d::Zero()) * look);
  return spec;
}

std::vector<uint32_t> TargetIds(const synth::RenderedFrame& truth) {
  std::vector<uint32_t> ids = truth.flat.at("instanceid").Get("id").uints;
  for (uint32_t& id : ids)
    if (id == 1000) id = 0;
  return ids;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void ExpectCameraNear(const CameraTruth& got,
                      const CameraTruth& want,
                      double relative,
                      double pose) {
  const PinholeCamera& a = got.intrinsics;
  const PinholeCamera& b = want.intrinsics;
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_NEAR(a.fx, b.fx, relative * b.fx);
  EXPECT_NEAR(a.fy, b.fy, relative * b.fy);
  EXPECT_NEAR(a.cx, b.cx, relative * b.cx);
  EXPECT_NEAR(a.cy, b.cy, relative * b.cy);
  EXPECT_LT((got.cam_from_world_rotation - want.cam_from_world_rotation).cwiseAbs().maxCoeff(),
            pose);
  EXPECT_LT((got.cam_from_world_translation - want.cam_from_world_translation).norm(), pose);
}

void ExpectObjectNear(const ObjectTruth& got, const ObjectTruth& want, double obb) {
  EXPECT_EQ(got.bbox, want.bbox);  // exact
  EXPECT_EQ(got.visible_pixels, want.visible_pixels);
  EXPECT_NEAR(got.visibility, want.visibility, 1e-12);
  EXPECT_NEAR(got.in_frame, want.in_frame, 1e-9 + 10 * obb);
  ASSERT_EQ(got.obb.has_value(), want.obb.has_value());
  if (!got.obb) return;
  EXPECT_LT((got.obb->center - want.obb->center).norm(), obb);
  EXPECT_LT((got.obb->half_extents - want.obb->half_extents).norm(), obb);
  EXPECT_LT((got.obb->world_from_box - want.obb->world_from_box).cwiseAbs().maxCoeff(), obb);
}

fs::path ExpectValidatesAndConvertsToCoco(const fs::path& collection, const fs::path& coco) {
  const CommandResult validate =
      RunCommandLine(LsdsBinary() + " validate --fail-on warning " + collection.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;
  const CommandResult convert = RunCommandLine(LsdsBinary() + " convert " + collection.string() +
                                               " --to coco --images none -o " + coco.string());
  EXPECT_EQ(convert.exit_code, 0) << convert.output;
  fs::path annotations;
  if (convert.exit_code != 0) return annotations;
  for (const auto& entry : fs::recursive_directory_iterator(coco))
    if (entry.path().extension() == ".json" &&
        entry.path().filename().string().rfind("instances", 0) == 0)
      annotations = entry.path();
  EXPECT_FALSE(annotations.empty());
  return annotations;
}

fs::path ExpectImportValidatesAndConverts(const std::string& format,
                                          const fs::path& source,
                                          const fs::path& dir,
                                          int w,
                                          int h,
                                          const FixtureIds& fixture_ids,
                                          const std::string& flags) {
  const fs::path out = dir / "collection";
  const CommandResult imported =
      RunCommandLine(LsdsBinary() + " import " + format + " " + source.string() + " -o " +
                     out.string() + " " + flags);
  EXPECT_EQ(imported.exit_code, 0) << imported.output;
  if (imported.exit_code != 0) return out;
  // COCO: every annotation's RLE mask is the fixture's mask of its instance.
  const fs::path annotations = ExpectValidatesAndConvertsToCoco(out, dir / "coco");
  if (annotations.empty()) return out;
  const json doc = json::parse(ReadText(annotations));
  std::map<int64_t, std::string> image_names;
  for (const json& image : doc["images"])
    image_names[image["id"].get<int64_t>()] = image["file_name"];
  EXPECT_GT(doc["annotations"].size(), 0u);
  for (const json& a : doc["annotations"]) {
    const int k = std::stoi(fs::path(image_names.at(a["image_id"].get<int64_t>())).stem().string());
    const std::vector<uint32_t> ids = fixture_ids(k);
    const uint32_t instance = a["lsds"]["instance_id"];
    int64_t total = 0;
    const cv::Mat mask =
        CocoDecode(CocoCountsFromString(a["segmentation"]["counts"]), h, w, &total);
    int64_t differing = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        differing +=
            (mask.at<uint8_t>(j, i) != 0) != (ids[static_cast<size_t>(j) * w + i] == instance);
    EXPECT_EQ(differing, 0) << "instance " << instance << " frame " << k;
  }

  // YOLO: one line per visible object, in truth order, whose normalised box
  // denormalises to the truth's pixel box (Ultralytics' label rule).
  const fs::path yolo = dir / "yolo";
  const CommandResult to_yolo = RunCommandLine(LsdsBinary() + " convert " + out.string() +
                                               " --to yolo --images none -o " + yolo.string());
  EXPECT_EQ(to_yolo.exit_code, 0) << to_yolo.output;
  // A label's class index names, in data.yaml, the object's class.
  const CollectionReader reader(out);
  // data.yaml: `  0: "box"  # lsds class id 2`.
  std::map<uint32_t, int> yolo_class;
  {
    std::istringstream yaml(ReadText(yolo / "data.yaml"));
    std::string line;
    const std::string tag = "# lsds class id ";
    while (std::getline(yaml, line)) {
      const size_t at = line.find(tag);
      if (line.rfind("  ", 0) != 0 || at == std::string::npos) continue;
      yolo_class[static_cast<uint32_t>(std::stoul(line.substr(at + tag.size())))] =
          std::stoi(line.substr(2, line.find(':') - 2));
    }
  }
  EXPECT_FALSE(yolo_class.empty());
  reader.ForEachFrame([&](const Frame& frame) {
    std::istringstream labels(
        ReadText(yolo / "labels" / "train" / (FrameStem(frame.index) + ".txt")));
    std::vector<const ObjectTruth*> visible;
    for (const ObjectTruth& o : frame.objects)
      if (o.visible_pixels > 0) visible.push_back(&o);
    int cls;
    double xc, yc, bw, bh;
    size_t n = 0;
    while (labels >> cls >> xc >> yc >> bw >> bh) {
      ASSERT_LT(n, visible.size());
      const ObjectTruth& o = *visible[n++];
      ASSERT_TRUE(yolo_class.count(o.class_id));
      EXPECT_EQ(cls, yolo_class.at(o.class_id));
      EXPECT_NEAR((xc - bw / 2) * w, o.bbox->x0, 1e-3);
      EXPECT_NEAR((xc + bw / 2) * w, o.bbox->x1, 1e-3);
      EXPECT_NEAR((yc - bh / 2) * h, o.bbox->y0, 1e-3);
      EXPECT_NEAR((yc + bh / 2) * h, o.bbox->y1, 1e-3);
    }
    EXPECT_EQ(n, visible.size()) << "frame " << frame.index;
  });
  return out;
}

}  // namespace lsds::testing
