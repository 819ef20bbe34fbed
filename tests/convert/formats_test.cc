// Every format end to end on synthesized collections with exact truth: masks
// decode to exactly the instance masks, boxes to the AABBs, splits are
// deterministic and grouped, filters are reported.
#include <cmath>
#include <cstdlib>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "converters/class_map.h"
#include "converters/split.h"
#include "converters/track_sequences.h"
#include "libs/masks/contours.h"
#include "libs/util/error.h"
#include "tests/build_paths.h"
#include "tests/convert/convert_test_util.h"
#include "tests/convert/reference_decoders.h"

namespace lsds::testing {
namespace {

using nlohmann::json;

constexpr uint32_t kSinglePixel = 7;
constexpr uint32_t kBorder = 8;

// The default scene plus a box covering exactly one pixel centre in frame 0 and
// a box cut by the left image border.
synth::Spec TestSpec() {
  synth::Spec spec = synth::DefaultSpec();
  const PinholeCamera camera =
      PinholeCamera::FromHorizontalFov(spec.width, spec.height, spec.hfov_deg);
  const Rigid3d world_from_cam = spec.cam_from_world[0].Inverse();
  const Eigen::Vector3d ray = camera.CamFromImage({40.5, 20.5});
  const Eigen::Vector3d top_in_world = world_from_cam * Eigen::Vector3d(ray / ray.z() * 19.0);
  synth::Box pixel;
  pixel.class_id = 3, pixel.instance_id = kSinglePixel, pixel.name = "crate#1";
  pixel.center = top_in_world - Eigen::Vector3d(0, 0, 0.05);
  pixel.half_extents = {0.05, 0.05, 0.05};
  synth::Box border;
  border.class_id = 2, border.instance_id = kBorder, border.name = "box#2";
  // Centred on the ray through the left border pixel (0, 24) at the box top, z
  // = 1.
  const Eigen::Vector3d edge = camera.CamFromImage({0.5, 24.5});
  border.center =
      world_from_cam * Eigen::Vector3d(edge / edge.z() * 19.0) - Eigen::Vector3d(0, 0, 0.5);
  border.half_extents = {1.0, 1.0, 0.5};
  spec.boxes.push_back(pixel);
  spec.boxes.push_back(border);
  return spec;
}

class ConvertTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    synth::WriteCollection(Collection(), TestSpec());
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path Collection() { return dir_->path() / "collection"; }
  fs::path Out(const std::string& name) const { return dir_->path() / name; }

  static TempDir* dir_;
};
TempDir* ConvertTest::dir_ = nullptr;

TEST_F(ConvertTest, PreconditionsOfTheTestScene) {
  const std::vector<Frame> frames = Frames(Collection());
  ASSERT_EQ(frames.size(), 4u);
  bool single = false, border = false;
  for (const ObjectTruth& o : frames[0].objects) {
    if (o.instance_id == kSinglePixel) single = o.visible_pixels == 1;
    if (o.instance_id == kBorder) border = o.bbox && o.bbox->x0 == 0 && o.in_frame < 1;
  }
  EXPECT_TRUE(single);
  EXPECT_TRUE(border);
}

// COCO polygons on the synthetic collection, rasterized by pycocotools' own
// rule (rleFrPoly port): exactly the instance mask, its holes (if any) filled,
// and the loss report's IoU matches.
TEST_F(ConvertTest, CocoPolygonsRasterizeToTheInstanceMask) {
  const fs::path out = Out("coco_polygon_exact");
  convert::ConvertOptions options = Options(Collection(), out, {"coco"});
  options.segmentation = "polygon";
  const convert::ConvertResult result = convert::Convert(options);
  const json coco = json::parse(ReadText(out / "annotations" / "instances_train.json"));
  std::map<int64_t, Frame> by_image;
  for (const Frame& f : Frames(Collection())) by_image[f.index + 1] = f;
  int exact = 0;
  for (const json& a : coco["annotations"]) {
    const Frame& frame = by_image.at(a["image_id"]);
    const cv::Mat mask = InstanceMask(Collection(), frame, a["lsds"]["instance_id"]) != 0;
    cv::Mat padded;
    cv::copyMakeBorder(mask, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
    cv::floodFill(padded, cv::Point(0, 0), 128, nullptr, 0, 0, 4);
    const cv::Mat filled = padded(cv::Rect(1, 1, 64, 48)) != 128;
    const cv::Mat decoded =
        CocoPolygonsToMask(a["segmentation"].get<std::vector<std::vector<double>>>(), 48, 64);
    EXPECT_EQ(cv::countNonZero((decoded != 0) != filled), 0)
        << "instance " << a["lsds"]["instance_id"] << " frame " << frame.index;
    exact += cv::countNonZero((decoded != 0) != mask) == 0;
  }
  EXPECT_GT(exact, 0);
  for (const auto& [name, iou] : result.loss.PolygonIou()) {
    EXPECT_GT(iou, 0.0) << name;
    EXPECT_LE(iou, 1.0) << name;
  }
}

TEST_F(ConvertTest, CocoRleDecodesToExactlyTheInstanceMask) {
  const fs::path out = Out("coco");
  const convert::ConvertResult result = convert::Convert(Options(Collection(), out, {"coco"}));
  EXPECT_EQ(result.frames, 4);
  const json coco = json::parse(ReadText(out / "annotations" / "instances_train.json"));
  const std::vector<Frame> frames = Frames(Collection());
  ASSERT_EQ(coco["images"].size(), frames.size());
  // Categories: the classes some annotation has, in class-table order, ids
  // 1..K (the ground has no truth objects and is not listed).
  ASSERT_EQ(coco["categories"].size(), 2u);
  EXPECT_EQ(coco["categories"][0]["name"], "box");
  EXPECT_EQ(coco["categories"][0]["id"], 1);
  EXPECT_EQ(coco["categories"][0]["lsds"]["class_ids"], json::array({2}));

  std::map<int64_t, const Frame*> by_image;
  for (const Frame& f : frames) by_image[f.index + 1] = &f;
  size_t expected = 0;
  for (const Frame& f : frames) {
    for (const ObjectTruth& o : f.objects) expected += o.visible_pixels > 0;
  }
  ASSERT_EQ(coco["annotations"].size(), expected);
  std::set<int64_t> ids;
  bool saw_single = false, saw_border = false;
  for (const json& a : coco["annotations"]) {
    ids.insert(a["id"].get<int64_t>());
    const Frame& frame = *by_image.at(a["image_id"]);
    const uint32_t instance = a["lsds"]["instance_id"];
    const ObjectTruth* truth = nullptr;
    for (const ObjectTruth& o : frame.objects) {
      if (o.instance_id == instance) truth = &o;
    }
    ASSERT_NE(truth, nullptr);
    const cv::Mat expected_mask = InstanceMask(Collection(), frame, instance);
    EXPECT_EQ(a["segmentation"]["size"], json::array({48, 64}));
    int64_t total = 0;
    const cv::Mat decoded =
        CocoDecode(CocoCountsFromString(a["segmentation"]["counts"]), 48, 64, &total);
    EXPECT_EQ(total, 48 * 64);
    EXPECT_TRUE(SameMask(decoded, expected_mask))
        << "instance " << instance << " frame " << frame.index;
    EXPECT_EQ(a["area"], cv::countNonZero(expected_mask));
    EXPECT_EQ(a["iscrowd"], 0);
    EXPECT_EQ(a["category_id"],
              truth->class_id - 1);  // classes 2, 3 -> categories 1, 2
    const Box2d& b = *truth->bbox;
    EXPECT_EQ(a["bbox"], json::array({b.x0, b.y0, b.width(), b.height()}));
    // The mask's extent is the box.
    const cv::Rect r = cv::boundingRect(expected_mask);
    EXPECT_EQ(r.x, b.x0);
    EXPECT_EQ(r.x + r.width, b.x1);
    if (instance == kSinglePixel && frame.index == 0) {
      saw_single = true;
      EXPECT_EQ(a["area"], 1);
      EXPECT_EQ(a["bbox"], json::array({40.0, 20.0, 1.0, 1.0}));
    }
    if (instance == kBorder && frame.index == 0) {
      saw_border = true;
      EXPECT_EQ(a["bbox"][0], 0.0);
      EXPECT_LT(a["lsds"]["in_frame"].get<double>(), 1.0);
    }
  }
  EXPECT_TRUE(saw_single);
  EXPECT_TRUE(saw_border);
  EXPECT_EQ(ids.size(), coco["annotations"].size());  // unique
  EXPECT_GT(result.loss.Total(convert::loss::kClippedAtBorder), 0);
}

TEST_F(ConvertTest, CvatMasksEqualInstanceMasksAndCocoMasks) {
  const fs::path out = Out("cvat_coco");
  convert::Convert(Options(Collection(), out, {"cvat", "coco"}));
  const std::string xml = ReadText(out / "annotations" / "cvat_train.xml");
  EXPECT_NE(xml.find("<version>1.1</version>"), std::string::npos);
  const json coco = json::parse(ReadText(out / "annotations" / "instances_train.json"));
  const auto masks = XmlElements(xml, "mask");
  const auto boxes = XmlElements(xml, "box");
  ASSERT_EQ(masks.size(), coco["annotations"].size());
  ASSERT_EQ(boxes.size(), masks.size());
  // Both list the kept objects frame by frame in the collection's order.
  for (size_t i = 0; i < masks.size(); ++i) {
    const auto& m = masks[i];
    int64_t total = 0;
    const cv::Mat cvat = CvatDecode(m.at("rle"),
                                    std::stoi(m.at("left")),
                                    std::stoi(m.at("top")),
                                    std::stoi(m.at("width")),
                                    std::stoi(m.at("height")),
                                    64,
                                    48,
                                    &total);
    EXPECT_EQ(total, std::stoll(m.at("width")) * std::stoll(m.at("height")));
    const json& a = coco["annotations"][i];
    int64_t coco_total = 0;
    const cv::Mat from_coco =
        CocoDecode(CocoCountsFromString(a["segmentation"]["counts"]), 48, 64, &coco_total);
    EXPECT_TRUE(SameMask(cvat, from_coco)) << "annotation " << i;
    // The CVAT box is the COCO box in corner form; the mask box is its integer
    // form.
    EXPECT_NEAR(std::stod(boxes[i].at("xtl")), a["bbox"][0].get<double>(), 1e-9);
    EXPECT_NEAR(std::stod(boxes[i].at("xbr")),
                a["bbox"][0].get<double>() + a["bbox"][2].get<double>(),
                1e-9);
    EXPECT_EQ(std::stoi(m.at("left")), a["bbox"][0].get<int>());
    EXPECT_EQ(std::stoi(m.at("width")), a["bbox"][2].get<int>());
    EXPECT_EQ(m.at("occluded"), a["lsds"]["visibility"].get<double>() < 1.0 ? "1" : "0");
  }
  EXPECT_EQ(XmlElements(xml, "image").size(), 4u);
}

TEST_F(ConvertTest, YoloBoxesDenormalizeToTheAabb) {
  const fs::path out = Out("yolo");
  convert::Convert(Options(Collection(), out, {"yolo"}));
  const std::string yaml = ReadText(out / "data.yaml");
  // The ground has no truth objects: it is not listed, and the ids of the
  // classes that occur are contiguous, each with its lsds class id.
  EXPECT_NE(yaml.find("names:\n  0: \"box\"  # lsds class id 2\n"
                      "  1: \"crate\"  # lsds class id 3\n"),
            std::string::npos)
      << yaml;
  // No absolute `path:`: the dataset root is the folder of data.yaml.
  EXPECT_EQ(yaml.find("path:"), std::string::npos);
  EXPECT_NE(yaml.find("train: images/train\nval: images/train\n"), std::string::npos);
  for (const Frame& frame : Frames(Collection())) {
    std::istringstream labels(
        ReadText(out / "labels" / "train" / (FrameStem(frame.index) + ".txt")));
    std::vector<const ObjectTruth*> visible;
    for (const ObjectTruth& o : frame.objects) {
      if (o.visible_pixels > 0) visible.push_back(&o);
    }
    int cls;
    double xc, yc, w, h;
    size_t n = 0;
    while (labels >> cls >> xc >> yc >> w >> h) {
      ASSERT_LT(n, visible.size());
      const ObjectTruth& o = *visible[n++];
      EXPECT_EQ(cls, static_cast<int>(o.class_id) - 2);
      for (double v : {xc, yc, w, h}) {
        EXPECT_GE(v, 0.0);
        EXPECT_LE(v, 1.0);
      }
      EXPECT_NEAR((xc - w / 2) * 64, o.bbox->x0, 0.5);
      EXPECT_NEAR((xc + w / 2) * 64, o.bbox->x1, 0.5);
      EXPECT_NEAR((yc - h / 2) * 48, o.bbox->y0, 0.5);
      EXPECT_NEAR((yc + h / 2) * 48, o.bbox->y1, 0.5);
    }
    EXPECT_EQ(n, visible.size());
  }
}

TEST_F(ConvertTest, YoloSegPolygonsLieInsideTheirBoxes) {
  const fs::path out = Out("yolo_seg");
  const convert::ConvertResult result = convert::Convert(Options(Collection(), out, {"yolo-seg"}));
  const json coco_like = nullptr;
  for (const Frame& frame : Frames(Collection())) {
    std::istringstream labels(
        ReadText(out / "labels" / "train" / (FrameStem(frame.index) + ".txt")));
    std::vector<const ObjectTruth*> visible;
    for (const ObjectTruth& o : frame.objects) {
      if (o.visible_pixels > 0) visible.push_back(&o);
    }
    std::string line;
    size_t n = 0;
    while (std::getline(labels, line)) {
      ASSERT_LT(n, visible.size());
      const ObjectTruth& o = *visible[n++];
      std::istringstream in(line);
      int cls;
      in >> cls;
      EXPECT_EQ(cls, static_cast<int>(o.class_id) - 2);  // ground not listed
      std::vector<double> v;
      double x;
      while (in >> x) v.push_back(x);
      ASSERT_EQ(v.size() % 2, 0u);
      ASSERT_GE(v.size(), 6u);  // at least a triangle
      for (size_t k = 0; k < v.size(); k += 2) {
        EXPECT_GE(v[k] * 64, o.bbox->x0 - 1e-4);
        EXPECT_LE(v[k] * 64, o.bbox->x1 + 1e-4);
        EXPECT_GE(v[k + 1] * 48, o.bbox->y0 - 1e-4);
        EXPECT_LE(v[k + 1] * 48, o.bbox->y1 + 1e-4);
      }
      // Ultralytics' polygon2mask (ultralytics/data/utils.py: the float32
      // label values times the image size, cast to int32, cv2.fillPoly with
      // the boundary) gives back exactly the instance mask.
      std::vector<cv::Point> truncated;
      for (size_t k = 0; k < v.size(); k += 2) {
        truncated.emplace_back(static_cast<int32_t>(static_cast<float>(v[k]) * 64.0f),
                               static_cast<int32_t>(static_cast<float>(v[k + 1]) * 48.0f));
      }
      cv::Mat rasterized = cv::Mat::zeros(48, 64, CV_8U);
      cv::fillPoly(rasterized, std::vector<std::vector<cv::Point>>{truncated}, 1);
      const cv::Mat mask = InstanceMask(Collection(), frame, o.instance_id) != 0;
      EXPECT_EQ(cv::countNonZero(mask != (rasterized != 0)), 0)
          << "frame " << frame.index << " instance " << o.instance_id;
      if (o.instance_id == kSinglePixel && o.visible_pixels == 1) {
        // A single pixel is its pixel-edge square.
        EXPECT_EQ(v.size(), 8u);
      }
      // Ultralytics derives the box from the polygon (segment2box): it is the
      // object's pixel-edge box within the corner inset, not one pixel smaller.
      std::vector<cv::Point2d> points;
      for (size_t k = 0; k < v.size(); k += 2) points.emplace_back(v[k] * 64, v[k + 1] * 48);
      const cv::Rect2d box = UltralyticsSegmentToBox(points, 64, 48);
      EXPECT_NEAR(box.x, o.bbox->x0, masks::kCornerInset + 1e-4);
      EXPECT_NEAR(box.y, o.bbox->y0, masks::kCornerInset + 1e-4);
      EXPECT_NEAR(box.x + box.width, o.bbox->x1, masks::kCornerInset + 1e-4);
      EXPECT_NEAR(box.y + box.height, o.bbox->y1, masks::kCornerInset + 1e-4);
    }
    EXPECT_EQ(n, visible.size());
  }
  EXPECT_EQ(result.loss.Total(convert::loss::kPiecesMerged), 0);
  EXPECT_EQ(result.loss.Total(convert::loss::kPolygon2maskObjects), 0);
}

TEST_F(ConvertTest, CvatVideoHasOneTrackPerInstance) {
  const fs::path out = Out("cvat_video");
  convert::Convert(Options(Collection(), out, {"cvat-video"}));
  const std::string xml = ReadText(out / "annotations" / "cvat_video_train.xml");
  const auto tracks = XmlElements(xml, "track");
  std::set<uint32_t> instances;
  for (const Frame& frame : Frames(Collection())) {
    for (const ObjectTruth& o : frame.objects) {
      if (o.visible_pixels > 0) instances.insert(o.instance_id);
    }
  }
  EXPECT_EQ(tracks.size(), instances.size());
  EXPECT_NE(xml.find("<mode>interpolation</mode>"), std::string::npos);
  // Every track starts with a visible keyframe; frames are numbered within the
  // split.
  for (const auto& box : XmlElements(xml, "box")) {
    EXPECT_EQ(box.at("keyframe"), "1");
    EXPECT_LT(std::stoi(box.at("frame")), 4);
  }
}

// data.yaml's names keys and every label file's class indices of a YOLO
// output.
void ReadYoloClasses(const fs::path& out,
                     std::vector<int>* names,
                     std::vector<std::string>* listed,
                     std::set<int>* used) {
  std::istringstream yaml(ReadText(out / "data.yaml"));
  std::string line;
  bool in_names = false;
  while (std::getline(yaml, line)) {
    if (line == "names:") {
      in_names = true;
    } else if (in_names && line.rfind("  ", 0) == 0) {
      names->push_back(std::stoi(line.substr(2, line.find(':') - 2)));
      const size_t q = line.find('"');
      listed->push_back(line.substr(q + 1, line.find('"', q + 1) - q - 1));
    }
  }
  for (const auto& entry : fs::recursive_directory_iterator(out / "labels")) {
    std::istringstream labels(ReadText(entry.path()));
    while (std::getline(labels, line)) {
      if (!line.empty()) used->insert(std::stoi(line));
    }
  }
}

TEST_F(ConvertTest, UnusedClassesAreDroppedUnlessKeptAndUltralyticsAccepts) {
  // Only crates pass --classes ground,crate: the ground (no truth objects) is
  // dropped, the crate becomes class 0.
  for (const bool keep : {false, true}) {
    SCOPED_TRACE(keep ? "--keep-classes" : "default");
    const fs::path out = Out(keep ? "yolo-keep" : "yolo-used");
    convert::ConvertOptions options = Options(Collection(), out, {"yolo", "coco", "cvat"});
    options.classes = "ground,crate";
    options.keep_classes = keep;
    convert::Convert(options);
    std::vector<int> names;
    std::vector<std::string> listed;
    std::set<int> used;
    ReadYoloClasses(out, &names, &listed, &used);
    EXPECT_EQ(UltralyticsClassCheck(names, used), "");
    const json coco = json::parse(ReadText(out / "annotations" / "instances_train.json"));
    const std::string xml = ReadText(out / "annotations" / "cvat_train.xml");
    if (keep) {
      EXPECT_EQ(listed, (std::vector<std::string>{"ground", "crate"}));
      EXPECT_EQ(used, std::set<int>{1});
      EXPECT_EQ(coco["categories"].size(), 2u);
      EXPECT_NE(xml.find("<name>ground</name>"), std::string::npos);
    } else {
      EXPECT_EQ(listed, std::vector<std::string>{"crate"});
      EXPECT_EQ(used, std::set<int>{0});
      ASSERT_EQ(coco["categories"].size(), 1u);
      EXPECT_EQ(coco["categories"][0]["name"], "crate");
      for (const json& a : coco["annotations"]) EXPECT_EQ(a["category_id"], 1);
      EXPECT_EQ(xml.find("<name>ground</name>"), std::string::npos);
      EXPECT_NE(xml.find("<name>crate</name>"), std::string::npos);
    }
  }
  // The consumer's own rule catches what dropping classes avoids: ids with a
  // gap, or labels beyond the names.
  EXPECT_NE(UltralyticsClassCheck({0, 2}, {0}), "");
  EXPECT_NE(UltralyticsClassCheck({0}, {1}), "");
}

TEST_F(ConvertTest, FiltersAndClassesAreReported) {
  const fs::path out = Out("filtered");
  convert::ConvertOptions options = Options(Collection(), out, {"yolo"});
  options.min_pixels = 2;
  options.classes = "box=thing,crate=thing";
  options.drop_truncated = true;
  const convert::ConvertResult result = convert::Convert(options);
  EXPECT_NE(ReadText(out / "data.yaml").find("names:\n  0: \"thing\"  # lsds class id 2, 3\n"),
            std::string::npos);
  const json report = json::parse(ReadText(out / "loss_report.json"));
  EXPECT_GE(result.loss.Count(convert::loss::kMinPixels, "crate"),
            1);  // the single pixel
  EXPECT_GE(result.loss.Count(convert::loss::kTruncated, "box"),
            1);  // the border box
  EXPECT_EQ(report["counts"][convert::loss::kMinPixels]["per_class"]["crate"],
            result.loss.Count(convert::loss::kMinPixels, "crate"));
  EXPECT_NE(ReadText(out / "loss_report.txt").find(convert::loss::kMinPixels), std::string::npos);
  // Every kept object is class 0.
  for (const auto& entry : fs::directory_iterator(out / "labels" / "train")) {
    std::istringstream in(ReadText(entry.path()));
    std::string line;
    while (std::getline(in, line)) EXPECT_EQ(line.substr(0, 2), "0 ");
  }
}

TEST_F(ConvertTest, MinVisibilityDropsOccludedObjects) {
  convert::ConvertOptions options = Options(Collection(), Out("visible"), {"coco"});
  options.min_visibility = 0.999;
  const convert::ConvertResult result = convert::Convert(options);
  int64_t below = 0;
  for (const Frame& frame : Frames(Collection())) {
    for (const ObjectTruth& o : frame.objects)
      below += o.visible_pixels > 0 && o.visibility < 0.999;
  }
  EXPECT_EQ(result.loss.Total(convert::loss::kMinVisibility), below);
}

TEST_F(ConvertTest, RefusesNonEmptyOutputWithoutForce) {
  const fs::path out = Out("busy");
  fs::create_directories(out);
  std::ofstream(out / "keep.txt") << "x";
  EXPECT_THROW(convert::Convert(Options(Collection(), out, {"yolo"})), Error);
  EXPECT_TRUE(fs::exists(out / "keep.txt"));
  convert::ConvertOptions options = Options(Collection(), out, {"yolo"});
  options.force = true;
  convert::Convert(options);
  EXPECT_FALSE(fs::exists(out / "keep.txt"));
  EXPECT_TRUE(fs::exists(out / "data.yaml"));
  // An empty folder is fine without --force.
  const fs::path empty = Out("empty");
  fs::create_directories(empty);
  convert::Convert(Options(Collection(), empty, {"yolo"}));
  EXPECT_TRUE(fs::exists(empty / "data.yaml"));
}

TEST_F(ConvertTest, ImagesAreSrgbEncodedOnce) {
  const fs::path out = Out("images");
  convert::ConvertOptions options = Options(Collection(), out, {"yolo", "coco"});
  options.images = "png";
  options.display.tonemap = imaging::ToneMap::kClamp;  // the encoding alone
  const convert::ConvertResult result = convert::Convert(options);
  EXPECT_EQ(result.images_written, 4);
  const Frame frame = Frames(Collection())[1];
  const cv::Mat png =
      cv::imread((out / "images" / "train" / "000001.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(png.type(), CV_8UC3);
  exr::FlatImage rgb = exr::ReadFlatExr(Collection() / frame.files.at("rgb"), {"R", "G", "B"});
  auto srgb = [](double v) {
    v = std::clamp(v, 0.0, 1.0);
    return std::lround(255 * (v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055));
  };
  for (int y = 0; y < 48; y += 7) {
    for (int x = 0; x < 64; x += 5) {
      const cv::Vec3b p = png.at<cv::Vec3b>(y, x);
      EXPECT_NEAR(p[2], srgb(rgb.F("R", x, y)), 1);
      EXPECT_NEAR(p[1], srgb(rgb.F("G", x, y)), 1);
      EXPECT_NEAR(p[0], srgb(rgb.F("B", x, y)), 1);
    }
  }
  const json coco = json::parse(ReadText(out / "annotations" / "instances_train.json"));
  EXPECT_EQ(coco["images"][1]["file_name"], "000001.png");
}

TEST_F(ConvertTest, OutputIsDeterministic) {
  convert::ConvertOptions a = Options(Collection(), Out("det_a"), {"coco", "cvat"});
  convert::ConvertOptions b = Options(Collection(), Out("det_b"), {"coco", "cvat"});
  a.batch_size = 1;  // different batching, same files
  convert::Convert(a);
  convert::Convert(b);
  for (const char* file :
       {"annotations/instances_train.json", "annotations/cvat_train.xml", "loss_report.json"}) {
    EXPECT_EQ(ReadText(Out("det_a") / file), ReadText(Out("det_b") / file)) << file;
  }
}

TEST_F(ConvertTest, CommandLineExitCodes) {
  const std::string lsds = ::lsds::testing::BinaryDir() + "/tools/lsds";
  const std::string out = (Out("cli")).string();
  const std::string ok =
      lsds + " convert " + Collection().string() + " --to yolo --images none -q -o " + out;
  EXPECT_EQ(std::system(ok.c_str()), 0);
  EXPECT_EQ(WEXITSTATUS(std::system((ok + " 2>/dev/null").c_str())),
            2);  // not empty, no --force
  EXPECT_EQ(WEXITSTATUS(std::system((ok + " --force").c_str())), 0);
  const std::string bad =
      lsds + " convert " + Collection().string() + " --to yollo -o " + out + "x 2>/dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 2);
  const std::string split = lsds + " convert " + Collection().string() +
                            " --to coco --split train=0.5,val=0.4 -o " + out + "y 2>/dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system(split.c_str())), 2);
}

// The tracking formats' sequences (docs/convert.md, "Sequences"): one per
// sequence, shot and rig camera, frames numbered 1.. in order, track ids 1.. by
// first appearance, file names made unique.
TEST(TrackSequences, OnePerShotAndRigCameraNumberedFromOne) {
  std::vector<Frame> frames;
  for (int step = 0; step < 3; ++step) {
    for (const char* camera : {"left", "right"}) {
      Frame f;
      f.index = static_cast<int64_t>(frames.size());
      f.time = 0.5 * step;
      f.sequence = "P1(1)";
      f.shot = step < 2 ? 0 : 4;  // a new shot at step 2 (frame 4)
      f.rig_camera = camera;
      f.step = step;
      frames.push_back(f);
    }
  }
  convert::TrackSequences sequences;
  std::vector<std::pair<std::string, int64_t>> added;  // (name, number) per frame
  for (const Frame& f : frames) {
    convert::FrameContext ctx;
    ctx.frame = &f;
    ctx.split = "train";
    ctx.width = 8;
    ctx.height = 6;
    const convert::TrackSequence& s = sequences.Add(ctx);
    added.emplace_back(s.name, s.frames());
  }
  const std::vector<std::pair<std::string, int64_t>> expected = {{"P1_1_-shot0-left", 1},
                                                                 {"P1_1_-shot0-right", 1},
                                                                 {"P1_1_-shot0-left", 2},
                                                                 {"P1_1_-shot0-right", 2},
                                                                 {"P1_1_-shot4-left", 1},
                                                                 {"P1_1_-shot4-right", 1}};
  EXPECT_EQ(added, expected);
  const auto train = sequences.OfSplit("train");
  ASSERT_EQ(train.size(), 4u);
  EXPECT_EQ(train[1]->frame_indices, (std::vector<int64_t>{1, 3}));
  EXPECT_DOUBLE_EQ(train[0]->FrameRate(), 2.0);  // 0.5 s steps
  EXPECT_DOUBLE_EQ(train[2]->FrameRate(), 1.0);  // one frame
  EXPECT_TRUE(sequences.OfSplit("val").empty());

  convert::TrackSequence s;
  EXPECT_EQ(s.TrackId(17), 1);
  EXPECT_EQ(s.TrackId(5), 2);
  EXPECT_EQ(s.TrackId(17), 1);

  // Two sequence names that make the same file name.
  Frame a, b;
  a.sequence = "a b";
  b.sequence = "a_b";
  convert::FrameContext ca, cb;
  ca.frame = &a;
  cb.frame = &b;
  ca.split = cb.split = "train";
  convert::TrackSequences clash;
  EXPECT_EQ(clash.Add(ca).name, "a_b");
  EXPECT_EQ(clash.Add(cb).name, "a_b-2");
}

TEST(Splits, DeterministicGroupedAndProportional) {
  const auto parts = convert::ParseSplit("train=0.7,val=0.2,test=0.1");
  ASSERT_EQ(parts.size(), 3u);
  EXPECT_THROW(convert::ParseSplit("train=0.7,val=0.2"), Error);
  EXPECT_THROW(convert::ParseSplit("train=1,train=0"), Error);
  EXPECT_THROW(convert::ParseSplit("train"), Error);
  EXPECT_EQ(convert::Fnv1a64(""), 14695981039346656037ull);
  EXPECT_EQ(convert::Fnv1a64("a"),
            0xaf63dc4c8601ec8cull);  // the FNV-1a 64 test vector
  std::map<std::string, int> counts;
  for (int g = 0; g < 2000; ++g) {
    const std::string group = "sequence_" + std::to_string(g);
    const std::string& split = convert::AssignSplit(parts, group);
    EXPECT_EQ(split, convert::AssignSplit(parts, group));
    ++counts[split];
  }
  EXPECT_NEAR(counts["train"], 1400, 100);
  EXPECT_NEAR(counts["val"], 400, 80);
  EXPECT_NEAR(counts["test"], 200, 60);
  // Frames of one sequence share a split; frames without one go by blocks of
  // consecutive indices.
  Frame a, b, c;
  a.sequence = b.sequence = "flight-3";
  a.index = 0, b.index = 999;
  EXPECT_EQ(convert::SplitGroup(a), convert::SplitGroup(b));
  c.index = 49;
  Frame d;
  d.index = 10;
  EXPECT_EQ(convert::SplitGroup(c), convert::SplitGroup(d));
}

TEST_F(ConvertTest, OneSequenceStillFillsEverySplit) {
  // The README's split on a one-sequence collection (4 frames): the hash rule
  // would put the whole sequence in one split, so contiguous blocks are cut.
  const fs::path out = Out("split");
  convert::ConvertOptions options = Options(Collection(), out, {"yolo", "coco"});
  options.split = "train=0.8,val=0.2";
  options.images = "png";
  convert::Convert(options);
  const json train = json::parse(ReadText(out / "annotations" / "instances_train.json"));
  const json val = json::parse(ReadText(out / "annotations" / "instances_val.json"));
  EXPECT_EQ(train["images"].size(), 3u);
  EXPECT_EQ(val["images"].size(), 1u);
  // Blocks are contiguous: train holds the first frames.
  EXPECT_EQ(val["images"][0]["lsds"]["frame"], 3);
  EXPECT_FALSE(fs::is_empty(out / "images" / "train"));
  EXPECT_FALSE(fs::is_empty(out / "images" / "val"));
  const std::string yaml = ReadText(out / "data.yaml");
  EXPECT_NE(yaml.find("val: images/val\n"), std::string::npos);
  // Relative to its own folder: no absolute path inside.
  EXPECT_EQ(yaml.find(fs::absolute(out).string()), std::string::npos);
  EXPECT_EQ(yaml.find("\npath:"), std::string::npos);
}

TEST(Splits, WholeSequencesWhenTheyFillEverySplit) {
  std::vector<convert::SplitFrame> frames;
  for (int s = 0; s < 40; ++s) {
    for (int i = 0; i < 5; ++i) frames.push_back({s * 5 + i, "seq_" + std::to_string(s)});
  }
  const auto parts = convert::ParseSplit("train=0.8,val=0.2");
  const convert::SplitPlan plan = convert::PlanSplits(parts, frames);
  EXPECT_FALSE(plan.blocks);
  for (const auto& f : frames) {
    EXPECT_EQ(plan.SplitOf(f.index), convert::AssignSplit(parts, f.group));
  }
  // Too few frames for the splits: a loud error naming the split.
  const auto three = convert::ParseSplit("train=0.5,val=0.3,test=0.2");
  try {
    convert::PlanSplits(three, {{0, "a"}, {1, "a"}});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot fill split 'test'"), std::string::npos)
        << e.what();
  }
  // A zero fraction may stay empty.
  const auto zero = convert::ParseSplit("train=1,val=0");
  EXPECT_FALSE(convert::PlanSplits(zero, {{0, "a"}}).blocks);
}

TEST(Splits, PlanAnswersPerFrameInAnyOrderAndARepeatedIndexTakesItsLastGroup) {
  const auto parts = convert::ParseSplit("train=0.5,val=0.5");
  // Groups whose hash lands in different splits: a repeated frame index
  // takes the split of its last entry.
  std::string in_train, in_val;
  for (int g = 0; in_train.empty() || in_val.empty(); ++g) {
    const std::string group = "g" + std::to_string(g);
    (convert::AssignSplit(parts, group) == "train" ? in_train : in_val) = group;
  }
  const std::vector<convert::SplitFrame> frames = {
      {9, in_val}, {-3, in_train}, {4, in_val}, {9, in_train}, {100, in_val}};
  const convert::SplitPlan plan = convert::PlanSplits(parts, frames);
  EXPECT_FALSE(plan.blocks);
  EXPECT_EQ(plan.SplitOf(9), "train");
  EXPECT_EQ(plan.SplitOf(-3), "train");
  EXPECT_EQ(plan.SplitOf(4), "val");
  EXPECT_EQ(plan.SplitOf(100), "val");
  EXPECT_THROW(plan.SplitOf(5), std::out_of_range);
  // The block rule (one group cannot fill two splits) answers the same way.
  const convert::SplitPlan blocks =
      convert::PlanSplits(parts, {{7, "one"}, {2, "one"}, {5, "one"}, {3, "one"}});
  EXPECT_TRUE(blocks.blocks);
  EXPECT_EQ(blocks.SplitOf(2), "train");
  EXPECT_EQ(blocks.SplitOf(3), "train");
  EXPECT_EQ(blocks.SplitOf(5), "val");
  EXPECT_EQ(blocks.SplitOf(7), "val");
}

TEST(ClassMap, OnlyUsedKeepsOrderReindexesAndKeepsMergedClassesWhole) {
  const std::vector<ClassInfo> classes = {{1, "ground"}, {2, "car"}, {3, "truck"}, {4, "person"}};
  const auto all = convert::ClassMap::All(classes);
  const auto used = all.OnlyUsed({4, 2});
  ASSERT_EQ(used.classes().size(), 2u);
  EXPECT_EQ(used.classes()[0].name, "car");
  EXPECT_EQ(used.classes()[1].name, "person");
  EXPECT_EQ(used.Map(2), 0);
  EXPECT_EQ(used.Map(4), 1);
  EXPECT_FALSE(used.Map(1).has_value());
  EXPECT_FALSE(used.Map(3).has_value());
  // A merged class is kept when any of its sources occurs, with all of them.
  const auto merged =
      convert::ClassMap::Parse("car=vehicle,truck=vehicle,person", classes).OnlyUsed({3});
  ASSERT_EQ(merged.classes().size(), 1u);
  EXPECT_EQ(merged.Map(2), 0);
  EXPECT_EQ(merged.Map(3), 0);
  EXPECT_TRUE(all.OnlyUsed({}).classes().empty());
}

TEST(ClassMap, SubsetRenameMergeAndErrors) {
  const std::vector<ClassInfo> classes = {{1, "ground"}, {2, "car"}, {3, "truck"}, {4, "person"}};
  const auto map = convert::ClassMap::Parse("person, car=vehicle, 3=vehicle", classes);
  ASSERT_EQ(map.classes().size(), 2u);
  EXPECT_EQ(map.classes()[0].name, "person");
  EXPECT_EQ(map.classes()[1].name, "vehicle");
  EXPECT_EQ(map.Map(2), 1);
  EXPECT_EQ(map.Map(3), 1);
  EXPECT_EQ(map.Map(4), 0);
  EXPECT_FALSE(map.Map(1).has_value());
  try {
    convert::ClassMap::Parse("persn", classes);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'person'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(convert::ClassMap::Parse("car,car=x", classes), Error);
}

}  // namespace
}  // namespace lsds::testing

namespace lsds::testing {
namespace {

// A crate cut in two by a pole standing on it, and a flat crate with a pillar
// in its middle (a hole): what polygons do with pieces and holes.
TEST(ConvertPolygons, PiecesAreBridgedAndHolesFilled) {
  TempDir dir;
  synth::Spec spec = synth::DefaultSpec();
  spec.boxes.clear();
  auto add = [&](uint32_t class_id, uint32_t id, Eigen::Vector3d center, Eigen::Vector3d half) {
    synth::Box box;
    box.class_id = class_id, box.instance_id = id;
    box.name = "b" + std::to_string(id);
    box.center = center, box.half_extents = half;
    spec.boxes.push_back(box);
  };
  add(3, 21, {0, -5, 0.3}, {0.4, 3, 0.3});    // long crate along image x
  add(2, 22, {0, -5, 2.5}, {1.0, 0.4, 2.5});  // pole across it
  add(3, 23, {0, 5, 0.2}, {2, 2, 0.2});       // flat crate
  add(2, 24, {0, 5, 2}, {0.5, 0.5, 2});       // pillar in its middle
  spec.cam_from_world = {synth::NadirCamFromWorld({0, 0, 20})};
  spec.layers = {"rgb", "classid", "instanceid"};
  const fs::path collection = dir.path() / "c";
  synth::WriteCollection(collection, spec);
  const Frame frame = Frames(collection)[0];

  const convert::ConvertResult seg =
      convert::Convert(Options(collection, dir.path() / "seg", {"yolo-seg"}));
  EXPECT_EQ(seg.loss.Count(convert::loss::kPiecesMerged, "crate"), 1);
  EXPECT_EQ(seg.loss.Count(convert::loss::kHolesFilled, "crate"), 1);
  // Ultralytics' polygon2mask draws the bridge across the pole and fills the
  // pillar's hole: both crates are reported, with at least the hole's pixels
  // and one bridge pixel wrong.
  EXPECT_EQ(seg.loss.Count(convert::loss::kPolygon2maskObjects, "crate"), 2);
  EXPECT_GT(seg.loss.Count(convert::loss::kPolygon2maskPixels, "crate"),
            cv::countNonZero(InstanceMask(collection, frame, 24)));
  // The bridged polygon, filled, covers both pieces of the crate.
  std::istringstream labels(ReadText(dir.path() / "seg" / "labels" / "train" / "000000.txt"));
  std::string line;
  bool checked = false;
  size_t k = 0;
  while (std::getline(labels, line)) {
    const ObjectTruth& o = frame.objects[k++];
    if (o.instance_id != 21) continue;
    std::istringstream in(line);
    int cls;
    in >> cls;
    std::vector<cv::Point> points;
    double x, y;
    while (in >> x >> y) {
      // Ultralytics' polygon2mask: float32 times the size, cast to int32.
      points.emplace_back(static_cast<int32_t>(static_cast<float>(x) * 64.0f),
                          static_cast<int32_t>(static_cast<float>(y) * 48.0f));
    }
    cv::Mat filled = cv::Mat::zeros(48, 64, CV_8U);
    cv::fillPoly(filled, std::vector<std::vector<cv::Point>>{points}, 1);
    const cv::Mat mask = InstanceMask(collection, frame, 21);
    EXPECT_EQ(cv::countNonZero(mask & (filled == 0)), 0);
    checked = true;
  }
  EXPECT_TRUE(checked);

  convert::ConvertOptions options = Options(collection, dir.path() / "poly", {"coco"});
  options.segmentation = "polygon";
  const convert::ConvertResult poly = convert::Convert(options);
  EXPECT_EQ(poly.loss.Count(convert::loss::kPiecesSplit, "crate"), 1);
  // The loss report gives the IoU the filled hole costs: crate pixels over
  // crate pixels plus the pillar's.
  const int64_t crate_pixels = cv::countNonZero(InstanceMask(collection, frame, 21)) +
                               cv::countNonZero(InstanceMask(collection, frame, 23));
  const int64_t hole_pixels = cv::countNonZero(InstanceMask(collection, frame, 24));
  EXPECT_NEAR(poly.loss.PolygonIou().at("crate"),
              double(crate_pixels) / double(crate_pixels + hole_pixels),
              1e-12);
  EXPECT_LT(poly.loss.PolygonIou().at("crate"), 1.0);
  const json coco =
      json::parse(ReadText(dir.path() / "poly" / "annotations" / "instances_train.json"));
  for (const json& a : coco["annotations"]) {
    const uint32_t id = a["lsds"]["instance_id"];
    // pycocotools' rasterization of the polygons (frPyObjects + decode).
    const cv::Mat decoded =
        CocoPolygonsToMask(a["segmentation"].get<std::vector<std::vector<double>>>(), 48, 64);
    const cv::Mat mask = InstanceMask(collection, frame, id) != 0;
    if (id == 21) {
      EXPECT_EQ(a["segmentation"].size(), 2u);
    }
    if (id == 23) {
      EXPECT_EQ(a["segmentation"].size(), 1u);
      // The hole (the pillar) is filled: the mask plus the hole.
      const cv::Mat hole = InstanceMask(collection, frame, 24) != 0;
      EXPECT_EQ(cv::countNonZero((decoded != 0) != (mask | hole)), 0);
      EXPECT_GT(cv::countNonZero(hole), 0);
    } else {
      EXPECT_EQ(cv::countNonZero((decoded != 0) != mask), 0) << "id " << id;
    }
    // area stays the mask pixel count, not a polygon area.
    EXPECT_EQ(a["area"], cv::countNonZero(InstanceMask(collection, frame, id)));
  }
}

}  // namespace
}  // namespace lsds::testing
