// `lsds convert --tile`: every object's share in a tile equals a count made
// here on the instanceid layer, tile boxes map back to the frame boxes with the
// tile map, every format passes its checks on tiles, and tile images are
// crops of the frame images.
#include <map>
#include <set>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "converters/tiles.h"
#include "libs/collection/schema.h"
#include "libs/masks/contours.h"
#include "libs/util/error.h"
#include "tests/convert/convert_test_util.h"
#include "tests/convert/reference_decoders.h"

namespace lsds::testing {
namespace {

using nlohmann::json;

// The default scene (64 x 48) cut into 32 x 32 tiles sharing 8 pixels: tiles
// at x 0, 24, 32 and y 0, 16, so objects straddle tile borders.
constexpr int kTile = 32;
constexpr int kOverlap = 8;

class TilesTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    synth::WriteCollection(Collection(), synth::DefaultSpec());
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path Collection() { return dir_->path() / "collection"; }
  static fs::path Out(const std::string& name) { return dir_->path() / name; }

  static convert::ConvertOptions Tiled(const std::string& name, std::vector<std::string> formats) {
    convert::ConvertOptions options = Options(Collection(), Out(name), std::move(formats));
    options.tile = std::to_string(kTile);
    options.overlap = std::to_string(kOverlap);
    return options;
  }

  static TempDir* dir_;
};
TempDir* TilesTest::dir_ = nullptr;

// The mask pixels of `mask` inside `rect`, counted pixel by pixel.
int64_t CountInside(const cv::Mat& mask, const cv::Rect& rect) {
  int64_t n = 0;
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    for (int x = rect.x; x < rect.x + rect.width; ++x) n += mask.at<uint8_t>(y, x) != 0;
  }
  return n;
}

// The tight box of the non-zero pixels (from the points: OpenCV 4.6's
// boundingRect of an 8-bit image is short for some narrow images).
cv::Rect TightBox(const cv::Mat& mask) {
  std::vector<cv::Point> points;
  cv::findNonZero(mask, points);
  return cv::boundingRect(points);
}

const Frame& FrameOf(const std::vector<Frame>& frames, int64_t index) {
  for (const Frame& f : frames) {
    if (f.index == index) return f;
  }
  throw std::runtime_error("no frame " + std::to_string(index));
}

TEST(TileGrid, StartsFollowDotaImgSplit) {
  // DOTA_devkit ImgSplit.py (commit 9938855), SplitSingle lines 210-230:
  // left steps by subsize - gap (line 61); when
  // left + subsize >= width, left = max(width - subsize, 0) and that tile is
  // the last. Worked by hand for subsize 1024, gap 200 (the devkit defaults
  // are 1024 and 100):
  EXPECT_EQ(convert::TileStarts(2000, 1024, 200), (std::vector<int>{0, 824, 976}));
  EXPECT_EQ(convert::TileStarts(1024, 1024, 200), (std::vector<int>{0}));
  EXPECT_EQ(convert::TileStarts(1000, 1024, 200), (std::vector<int>{0}));
  EXPECT_EQ(convert::TileStarts(1848, 1024, 200), (std::vector<int>{0, 824}));
  // Properties for many sizes: the tiles cover the axis, start at 0, end on
  // the edge, lie inside, and neighbours share at least the overlap.
  for (int size = 1; size < 300; size += 7) {
    for (int tile : {16, 50, 64}) {
      for (int overlap : {0, 5, 15}) {
        const std::vector<int> s = convert::TileStarts(size, tile, overlap);
        const int width = std::min(tile, size);
        ASSERT_FALSE(s.empty());
        EXPECT_EQ(s.front(), 0);
        EXPECT_EQ(s.back() + width, size);
        for (size_t k = 1; k < s.size(); ++k) {
          EXPECT_GT(s[k], s[k - 1]);
          EXPECT_GE(s[k - 1] + width - s[k], overlap);
          EXPECT_LE(s[k] - s[k - 1], tile - overlap);
        }
      }
    }
  }
}

TEST(TileGrid, FlagsAreChecked) {
  convert::ConvertOptions options;
  options.tile = "32x16";
  options.overlap = "25%";
  convert::TileGrid grid = convert::ParseTileGrid(options);
  EXPECT_EQ(grid.width, 32);
  EXPECT_EQ(grid.height, 16);
  EXPECT_EQ(grid.overlap_x, 8);
  EXPECT_EQ(grid.overlap_y, 4);
  options.tile = "40";
  options.overlap = "10";
  grid = convert::ParseTileGrid(options);
  EXPECT_EQ(grid.height, 40);
  EXPECT_EQ(grid.overlap_y, 10);
  options.drop_truncated = true;
  EXPECT_EQ(convert::ParseTileGrid(options).min_fraction, 1.0);
  options.drop_truncated = false;
  for (const auto& [tile, overlap] :
       std::vector<std::pair<std::string, std::string>>{{"0", "0"},
                                                        {"32x", "0"},
                                                        {"-4", "0"},
                                                        {"3.5", "0"},
                                                        {"32", "32"},
                                                        {"32", "100%"},
                                                        {"32", "-1"},
                                                        {"32", "1.5"},
                                                        {"32", "x"},
                                                        {"32x0", "0"}}) {
    options.tile = tile;
    options.overlap = overlap;
    EXPECT_THROW(convert::ParseTileGrid(options), Error) << tile << " " << overlap;
  }
  options.tile = "32";
  options.overlap = "0";
  options.tile_min_fraction = 0;
  EXPECT_THROW(convert::ParseTileGrid(options), Error);
}

// The share of each object in each tile is the count of its instanceid pixels
// inside the tile over its count in the frame; the threshold decides who
// appears; every COCO mask is the instance mask cut to the tile.
TEST_F(TilesTest, TileFractionIsTheExactMaskShare) {
  for (double min_fraction : {1e-9, 0.5}) {
    const std::string name = "fraction_" + std::to_string(min_fraction);
    convert::ConvertOptions options = Tiled(name, {"coco"});
    options.tile_min_fraction = min_fraction;
    const convert::ConvertResult result = convert::Convert(options);
    const json map = json::parse(ReadText(Out(name) / "tiles.json"));
    EXPECT_TRUE(JsonSchema::Get("tiles.schema.json").Validate(map).empty());
    const json coco = json::parse(ReadText(Out(name) / "annotations" / "instances_train.json"));
    const std::vector<Frame> frames = Frames(Collection());
    // 3 tile columns x 2 rows per frame.
    ASSERT_EQ(map["tiles"].size(), frames.size() * 6);
    ASSERT_EQ(coco["images"].size(), map["tiles"].size());

    std::map<int64_t, std::vector<const json*>> annotations;  // by image id
    for (const json& a : coco["annotations"])
      annotations[a["image_id"].get<int64_t>()].push_back(&a);
    bool straddles = false;
    int64_t below = 0;
    for (size_t t = 0; t < map["tiles"].size(); ++t) {
      const json& tile = map["tiles"][t];
      const json& image = coco["images"][t];
      EXPECT_EQ(image["file_name"], tile["image"]);
      EXPECT_EQ(image["width"], kTile);
      EXPECT_EQ(image["height"], kTile);
      const Frame& frame = FrameOf(frames, tile["frame"].get<int64_t>());
      const cv::Rect rect(tile["x"].get<int>(),
                          tile["y"].get<int>(),
                          tile["width"].get<int>(),
                          tile["height"].get<int>());
      EXPECT_EQ(tile["image"],
                FrameStem(frame.index) + "_" + std::to_string(rect.x) + "_" +
                    std::to_string(rect.y) + ".png");
      // Independently: who should be here, with which share.
      std::vector<std::pair<uint32_t, double>> expected;
      for (const ObjectTruth& o : frame.objects) {
        if (o.visible_pixels <= 0) continue;
        const cv::Mat mask = InstanceMask(Collection(), frame, o.instance_id);
        const int64_t inside = CountInside(mask, rect);
        const int64_t total = cv::countNonZero(mask);
        if (inside == 0) continue;
        const double share = static_cast<double>(inside) / static_cast<double>(total);
        if (share < min_fraction) {
          ++below;
          continue;
        }
        straddles = straddles || share < 1;
        expected.emplace_back(o.instance_id, share);
      }
      const json& objects = tile["objects"];
      const std::vector<const json*>& tile_annotations = annotations[image["id"].get<int64_t>()];
      ASSERT_EQ(objects.size(), expected.size()) << "tile " << t;
      ASSERT_EQ(tile_annotations.size(), expected.size());
      for (size_t k = 0; k < expected.size(); ++k) {
        EXPECT_EQ(objects[k]["instance_id"], expected[k].first);
        EXPECT_DOUBLE_EQ(objects[k]["tile_fraction"].get<double>(), expected[k].second);
        // The COCO mask is the instance mask cut to the tile; the box is its
        // tight box, in tile coordinates.
        const json& a = *tile_annotations[k];
        EXPECT_EQ(a["lsds"]["instance_id"], expected[k].first);
        const cv::Mat cut = InstanceMask(Collection(), frame, expected[k].first)(rect);
        int64_t decoded_total = 0;
        const cv::Mat decoded = CocoDecode(
            CocoCountsFromString(a["segmentation"]["counts"]), kTile, kTile, &decoded_total);
        EXPECT_EQ(decoded_total, kTile * kTile);
        EXPECT_TRUE(SameMask(decoded, cut)) << "tile " << t << " object " << k;
        EXPECT_EQ(a["area"], cv::countNonZero(cut));
        EXPECT_EQ(a["lsds"]["visible_pixels"], cv::countNonZero(cut));
        const cv::Rect r = TightBox(cut);
        EXPECT_EQ(a["bbox"], json::array({r.x, r.y, r.width, r.height}));
      }
    }
    EXPECT_TRUE(straddles) << "the test scene must have an object cut by a tile border";
    EXPECT_EQ(result.loss.Total(convert::loss::kTileBelowFraction), below);
    if (min_fraction == 0.5) {
      EXPECT_GT(below, 0);
    }
  }
}

// Boxes of objects whole in a tile, moved by the tile's (x, y) from the tile
// map, are the frame's boxes (COCO exactly, YOLO to its printed precision).
TEST_F(TilesTest, WholeObjectsMapBackToTheFrameBoxes) {
  convert::Convert(Tiled("round_trip", {"coco"}));
  convert::Convert(Tiled("round_trip_yolo", {"yolo"}));
  const json map = json::parse(ReadText(Out("round_trip") / "tiles.json"));
  const json coco =
      json::parse(ReadText(Out("round_trip") / "annotations" / "instances_train.json"));
  const std::vector<Frame> frames = Frames(Collection());
  std::map<int64_t, size_t> tile_of_image;  // coco image id -> tile
  for (size_t t = 0; t < coco["images"].size(); ++t)
    tile_of_image[coco["images"][t]["id"].get<int64_t>()] = t;
  int whole = 0;
  std::map<size_t, int> seen_in_tile;
  for (const json& a : coco["annotations"]) {
    const size_t t = tile_of_image.at(a["image_id"].get<int64_t>());
    const json& tile = map["tiles"][t];
    const json& entry = tile["objects"][seen_in_tile[t]++];
    ASSERT_EQ(entry["instance_id"], a["lsds"]["instance_id"]);
    if (entry["tile_fraction"] != 1.0) continue;
    ++whole;
    const Frame& frame = FrameOf(frames, tile["frame"].get<int64_t>());
    const ObjectTruth* truth = nullptr;
    for (const ObjectTruth& o : frame.objects) {
      if (o.instance_id == a["lsds"]["instance_id"].get<uint32_t>()) truth = &o;
    }
    ASSERT_NE(truth, nullptr);
    const double x = tile["x"].get<double>(), y = tile["y"].get<double>();
    EXPECT_EQ(a["bbox"][0].get<double>() + x, truth->bbox->x0);
    EXPECT_EQ(a["bbox"][1].get<double>() + y, truth->bbox->y0);
    EXPECT_EQ(a["bbox"][2].get<double>(), truth->bbox->width());
    EXPECT_EQ(a["bbox"][3].get<double>(), truth->bbox->height());
    EXPECT_DOUBLE_EQ(a["lsds"]["in_frame"].get<double>(), truth->in_frame);

    // YOLO: the same tile's label line for this object.
    std::istringstream labels(ReadText(
        Out("round_trip_yolo") / "labels" / "train" /
        (tile["image"].get<std::string>().substr(0, tile["image"].get<std::string>().size() - 4) +
         ".txt")));
    int cls;
    double xc, yc, w, h;
    for (int k = 0; k < seen_in_tile[t]; ++k) labels >> cls >> xc >> yc >> w >> h;
    EXPECT_NEAR((xc - w / 2) * kTile + x, truth->bbox->x0, 1e-4);
    EXPECT_NEAR((xc + w / 2) * kTile + x, truth->bbox->x1, 1e-4);
    EXPECT_NEAR((yc - h / 2) * kTile + y, truth->bbox->y0, 1e-4);
    EXPECT_NEAR((yc + h / 2) * kTile + y, truth->bbox->y1, 1e-4);
  }
  EXPECT_GT(whole, 0);
}

// Every format on tiles: the files agree with the tile map and pass the
// checks the format tests apply; tile images are crops of the frame images.
TEST_F(TilesTest, EveryFormatWorksOnTiles) {
  convert::ConvertOptions options = Tiled("all_a", {"yolo-seg", "coco", "cvat", "cvat-video"});
  options.images = "png";
  const convert::ConvertResult result = convert::Convert(options);
  convert::ConvertOptions yolo = Tiled("all_b", {"yolo"});
  convert::Convert(yolo);
  convert::ConvertOptions whole = Options(Collection(), Out("all_frames"), {"yolo"});
  whole.images = "png";
  convert::Convert(whole);

  const fs::path out = Out("all_a");
  const json map = json::parse(ReadText(out / "tiles.json"));
  EXPECT_EQ(result.images_written, static_cast<int64_t>(map["tiles"].size()));
  const json coco = json::parse(ReadText(out / "annotations" / "instances_train.json"));
  const std::string xml = ReadText(out / "annotations" / "cvat_train.xml");
  const auto cvat_images = XmlElements(xml, "image");
  const auto cvat_masks = XmlElements(xml, "mask");
  ASSERT_EQ(cvat_images.size(), map["tiles"].size());
  ASSERT_EQ(cvat_masks.size(), coco["annotations"].size());
  std::set<int64_t> image_ids;
  for (const json& image : coco["images"]) image_ids.insert(image["id"].get<int64_t>());
  EXPECT_EQ(image_ids.size(), coco["images"].size());  // unique per tile

  size_t annotation = 0;
  for (size_t t = 0; t < map["tiles"].size(); ++t) {
    const json& tile = map["tiles"][t];
    const std::string image_name = tile["image"];
    const std::string stem = image_name.substr(0, image_name.size() - 4);
    EXPECT_EQ(cvat_images[t].at("name"), image_name);
    EXPECT_EQ(cvat_images[t].at("width"), std::to_string(kTile));

    // The image is the crop of the frame's image.
    const cv::Mat tile_png =
        cv::imread((out / "images" / "train" / image_name).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat frame_png = cv::imread(
        (Out("all_frames") / "images" / "train" / tile["frame_image"].get<std::string>()).string(),
        cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(tile_png.empty());
    const cv::Rect rect(tile["x"].get<int>(),
                        tile["y"].get<int>(),
                        tile["width"].get<int>(),
                        tile["height"].get<int>());
    EXPECT_EQ(cv::norm(tile_png, frame_png(rect), cv::NORM_INF), 0.0) << image_name;

    // YOLO: one line per object in the map, normalized to the tile.
    std::istringstream boxes(ReadText(Out("all_b") / "labels" / "train" / (stem + ".txt")));
    std::istringstream polygons(ReadText(out / "labels" / "train" / (stem + ".txt")));
    for (size_t k = 0; k < tile["objects"].size(); ++k, ++annotation) {
      const json& a = coco["annotations"][annotation];
      ASSERT_EQ(a["lsds"]["instance_id"], tile["objects"][k]["instance_id"]);
      int cls;
      double xc, yc, w, h;
      ASSERT_TRUE(boxes >> cls >> xc >> yc >> w >> h);
      EXPECT_EQ(cls, a["category_id"].get<int>() - 1);
      for (double v : {xc, yc, w, h}) {
        EXPECT_GE(v, 0.0);
        EXPECT_LE(v, 1.0);
      }
      EXPECT_NEAR((xc - w / 2) * kTile, a["bbox"][0].get<double>(), 1e-4);
      EXPECT_NEAR(w * kTile, a["bbox"][2].get<double>(), 1e-4);
      // YOLO-seg: Ultralytics' box of the polygon is the tile box.
      std::string line;
      ASSERT_TRUE(std::getline(polygons, line));
      std::istringstream in(line);
      in >> cls;
      std::vector<cv::Point2d> points;
      double px, py;
      while (in >> px >> py) points.emplace_back(px * kTile, py * kTile);
      ASSERT_GE(points.size(), 3u);
      const cv::Rect2d from_polygon = UltralyticsSegmentToBox(points, kTile, kTile);
      // Within the corner inset of yolo-seg's vertices on each side.
      EXPECT_NEAR(from_polygon.x, a["bbox"][0].get<double>(), masks::kCornerInset + 1e-4);
      EXPECT_NEAR(from_polygon.width, a["bbox"][2].get<double>(), 2 * masks::kCornerInset + 1e-4);
      EXPECT_NEAR(from_polygon.height, a["bbox"][3].get<double>(), 2 * masks::kCornerInset + 1e-4);
      // CVAT: the mask equals the COCO mask, in the tile.
      const auto& m = cvat_masks[annotation];
      int64_t total = 0, coco_total = 0;
      const cv::Mat cvat = CvatDecode(m.at("rle"),
                                      std::stoi(m.at("left")),
                                      std::stoi(m.at("top")),
                                      std::stoi(m.at("width")),
                                      std::stoi(m.at("height")),
                                      kTile,
                                      kTile,
                                      &total);
      const cv::Mat from_coco =
          CocoDecode(CocoCountsFromString(a["segmentation"]["counts"]), kTile, kTile, &coco_total);
      EXPECT_TRUE(SameMask(cvat, from_coco));
    }
    std::string extra;
    EXPECT_FALSE(boxes >> extra);  // no extra line
  }
  EXPECT_EQ(annotation, coco["annotations"].size());

  // CVAT video: a tiled video is one video per tile position, so an instance
  // has one track per tile position it is seen in.
  const std::string video = ReadText(out / "annotations" / "cvat_video_train.xml");
  const auto tracks = XmlElements(video, "track");
  std::set<std::pair<std::string, uint32_t>> positions;
  for (const json& tile : map["tiles"]) {
    const std::string position =
        std::to_string(tile["x"].get<int>()) + "_" + std::to_string(tile["y"].get<int>());
    for (const json& o : tile["objects"])
      positions.insert({position, o["instance_id"].get<uint32_t>()});
  }
  EXPECT_EQ(tracks.size(), positions.size());
}

// Oriented boxes of a rotated object cut by a tile border are measured on the
// id layer cut to the tile (MaskOrientedBox, here on the id layer itself); an
// object whole in a tile keeps its frame box, moved. Amodal boxes move.
TEST(TileCut, OrientedBoxesAreMeasuredOnTheCutMask) {
  constexpr int kWidth = 60, kHeight = 40;
  constexpr uint32_t kRotated = 5, kSmall = 6;
  cv::Mat ids = cv::Mat::zeros(kHeight, kWidth, CV_32S);
  // A rotated rectangle straddling x = 30, and a small square left of it.
  const std::vector<cv::Point> rotated = {{20, 8}, {44, 16}, {40, 28}, {16, 20}};
  cv::fillConvexPoly(ids, rotated, cv::Scalar(kRotated));
  cv::rectangle(ids, cv::Rect(4, 30, 5, 4), cv::Scalar(kSmall), cv::FILLED);
  std::vector<uint32_t> layer(ids.begin<int32_t>(), ids.end<int32_t>());

  Frame frame;
  frame.index = 3;
  frame.sequence = "S";
  frame.camera.intrinsics = PinholeCamera::FromHorizontalFov(kWidth, kHeight, 60);
  for (uint32_t id : {kRotated, kSmall}) {
    ObjectTruth o;
    o.instance_id = id;
    o.class_id = 1;
    o.in_frame = 1;
    o.visibility = 1;
    const cv::Rect r = TightBox(ids == static_cast<int>(id));
    o.bbox = Box2d{double(r.x), double(r.y), double(r.x + r.width), double(r.y + r.height)};
    o.bbox_projected = Box2d{o.bbox->x0 - 2, o.bbox->y0 - 2, o.bbox->x1 + 2, o.bbox->y1 + 2};
    o.bbox_oriented =
        MaskOrientedBox(layer.data(), kWidth, kHeight, id, Box2d{0, 0, kWidth, kHeight});
    ASSERT_TRUE(o.bbox_oriented);
    o.bbox_oriented_projected = o.bbox_oriented;
    o.visible_pixels = cv::countNonZero(ids == static_cast<int>(id));
    frame.objects.push_back(o);
  }
  convert::FrameContext ctx;
  ctx.frame = &frame;
  ctx.split = "train";
  ctx.stem = "000003";
  ctx.width = kWidth, ctx.height = kHeight;
  const auto bounds = masks::ComputeIdBounds(layer.data(), kWidth, kHeight);
  for (const ObjectTruth& o : frame.objects) {
    ctx.mask_storage.push_back(
        masks::ExtractMask(layer.data(), kWidth, kHeight, o.instance_id, bounds.at(o.instance_id)));
  }
  for (size_t i = 0; i < frame.objects.size(); ++i) {
    convert::KeptObject k;
    k.truth = &frame.objects[i];
    k.box = *frame.objects[i].bbox;
    k.mask = &ctx.mask_storage[i];
    k.oriented = frame.objects[i].bbox_oriented;
    ctx.objects.push_back(k);
  }

  TempDir dir;
  convert::ConvertOptions options;
  options.tile = "30x40";
  options.tile_min_fraction = 0.01;
  const convert::ClassMap classes = convert::ClassMap::All({{1, "thing"}});
  convert::Tiler tiler(options, classes, dir.path());
  convert::LossReport loss;
  const auto tiles = tiler.Cut(ctx, cv::Mat(), 10, &loss);
  ASSERT_EQ(tiles.size(), 2u);  // x = 0 and x = 30
  bool saw_cut = false, saw_whole = false;
  for (const auto& tile : tiles) {
    const int x = tile->rect.x;
    EXPECT_EQ(tile->context.image_index, 10 + (x == 0 ? 0 : 1));
    EXPECT_EQ(tile->frame.camera.intrinsics.width, 30);
    EXPECT_DOUBLE_EQ(tile->frame.camera.intrinsics.cx, frame.camera.intrinsics.cx - x);
    // The id layer cut to the tile.
    std::vector<uint32_t> cut;
    for (int row = 0; row < kHeight; ++row) {
      for (int col = x; col < x + 30; ++col) cut.push_back(layer[row * kWidth + col]);
    }
    for (size_t k = 0; k < tile->context.objects.size(); ++k) {
      const convert::KeptObject& object = tile->context.objects[k];
      const ObjectTruth& source = frame.objects[object.truth->instance_id == kRotated ? 0 : 1];
      ASSERT_TRUE(object.oriented);
      ASSERT_TRUE(object.truth->bbox_oriented);
      EXPECT_EQ(object.truth->bbox_oriented_projected->corners[0],
                source.bbox_oriented_projected->corners[0] - Eigen::Vector2d(x, 0));
      EXPECT_EQ(object.truth->bbox_projected->x0, std::max(0.0, source.bbox_projected->x0 - x));
      EXPECT_LE(object.truth->bbox_projected->x1, 30.0);
      if (tile->tile_fractions[k] == 1.0) {
        saw_whole = true;
        for (int c = 0; c < 4; ++c) {
          EXPECT_EQ(object.oriented->corners[c],
                    source.bbox_oriented->corners[c] - Eigen::Vector2d(x, 0));
        }
        continue;
      }
      saw_cut = true;
      const std::optional<OrientedBox2d> expected = MaskOrientedBox(
          cut.data(), 30, kHeight, object.truth->instance_id, Box2d{0, 0, 30, kHeight});
      ASSERT_TRUE(expected);
      // The same rectangle (corners as a set), first corner on the side of the
      // frame box's first corner.
      for (const Eigen::Vector2d& corner : object.oriented->corners) {
        double nearest = 1e9;
        for (const Eigen::Vector2d& e : expected->corners)
          nearest = std::min(nearest, (corner - e).norm());
        EXPECT_LT(nearest, 1e-9);
      }
      for (int c = 0; c < 4; ++c)
        EXPECT_EQ(object.truth->bbox_oriented->corners[c], object.oriented->corners[c]);
      const Eigen::Vector2d frame_side =
          (source.bbox_oriented->corners[0] + source.bbox_oriented->corners[1]) / 2 -
          source.bbox_oriented->Center();
      const Eigen::Vector2d tile_side =
          (object.oriented->corners[0] + object.oriented->corners[1]) / 2 -
          object.oriented->Center();
      EXPECT_GT(frame_side.dot(tile_side), 0);
      // Its box is the tight box of the cut mask.
      cv::Mat cut_mask(kHeight, 30, CV_8U);
      for (int i = 0; i < kHeight * 30; ++i) cut_mask.data[i] = cut[i] == object.truth->instance_id;
      const cv::Rect r = TightBox(cut_mask);
      EXPECT_EQ(object.box,
                (Box2d{double(r.x), double(r.y), double(r.x + r.width), double(r.y + r.height)}));
      EXPECT_EQ(object.truth->visible_pixels, cv::countNonZero(cut_mask));
    }
  }
  EXPECT_TRUE(saw_cut);
  EXPECT_TRUE(saw_whole);
  EXPECT_EQ(loss.Total(convert::loss::kTileTruncated), 2);  // the rotated box, in both tiles
}

TEST_F(TilesTest, BadTileFlagsWriteNothing) {
  convert::ConvertOptions options = Tiled("bad", {"coco"});
  options.overlap = std::to_string(kTile);
  EXPECT_THROW(convert::Convert(options), Error);
  EXPECT_FALSE(fs::exists(Out("bad")));
}

}  // namespace
}  // namespace lsds::testing
