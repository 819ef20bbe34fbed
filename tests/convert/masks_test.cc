// COCO and CVAT RLE and polygons against reference decoders, on hand-made and
// random masks.
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "libs/masks/coco_rle.h"
#include "libs/masks/contours.h"
#include "libs/masks/cvat_rle.h"
#include "libs/masks/instance_masks.h"
#include "tests/convert/reference_decoders.h"

namespace lsds::masks {
namespace {

using testing::CocoCountsFromString;
using testing::CocoDecode;
using testing::CvatDecode;
using testing::SameMask;

// The BoxMask of instance `id` of a full-image id map.
BoxMask MaskOf(const std::vector<uint32_t>& ids, int w, int h, uint32_t id) {
  const auto bounds = ComputeIdBounds(ids.data(), w, h);
  const auto it = bounds.find(id);
  BoxMask empty;
  empty.image_width = w;
  empty.image_height = h;
  return it == bounds.end() ? empty : ExtractMask(ids.data(), w, h, id, it->second);
}

cv::Mat FullMask(const std::vector<uint32_t>& ids, int w, int h, uint32_t id) {
  cv::Mat m(h, w, CV_8U);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) m.at<uint8_t>(y, x) = ids[y * w + x] == id;
  }
  return m;
}

void ExpectRoundTrips(const std::vector<uint32_t>& ids, int w, int h, uint32_t id) {
  const BoxMask mask = MaskOf(ids, w, h, id);
  const cv::Mat truth = FullMask(ids, w, h, id);
  EXPECT_EQ(mask.pixel_count, cv::countNonZero(truth));
  EXPECT_TRUE(SameMask(ToFullImage(mask), truth));

  const std::vector<uint32_t> counts = CocoRleCounts(mask);
  const std::string coco = CocoRleToString(counts);
  EXPECT_EQ(CocoCountsFromString(coco), counts);
  int64_t total = 0;
  EXPECT_TRUE(SameMask(CocoDecode(CocoCountsFromString(coco), h, w, &total), truth));
  EXPECT_EQ(total, int64_t{w} * h);

  if (!mask.empty()) {
    int64_t cvat_total = 0;
    const cv::Mat cvat = CvatDecode(CvatRleToString(CvatRleCounts(mask)),
                                    mask.left,
                                    mask.top,
                                    mask.width(),
                                    mask.height(),
                                    w,
                                    h,
                                    &cvat_total);
    EXPECT_TRUE(SameMask(cvat, truth));
    EXPECT_EQ(cvat_total, int64_t{mask.width()} * mask.height());
  }
}

TEST(CocoRle, KnownEncodingOfTheCocoApi) {
  // pycocotools: mask [[0,1],[1,1]] (h=2, w=2, column-major 0,1,1,1) -> counts
  // [1,3] -> "13".
  std::vector<uint32_t> ids = {0, 5, 5, 5};
  const BoxMask mask = MaskOf(ids, 2, 2, 5);
  EXPECT_EQ(CocoRleCounts(mask), (std::vector<uint32_t>{1, 3}));
  EXPECT_EQ(CocoRleToString({1, 3}), "13");
  // Foreground first: a leading background run of 0.
  ids = {5, 0, 0, 0};
  EXPECT_EQ(CocoRleCounts(MaskOf(ids, 2, 2, 5)), (std::vector<uint32_t>{0, 1, 3}));
  // Large counts and negative deltas ("i > 2" quirk of rleToString).
  const std::vector<uint32_t> counts = {100000, 3, 7, 1, 99999, 2, 0};
  EXPECT_EQ(CocoCountsFromString(CocoRleToString(counts)), counts);
}

TEST(CocoRle, ColumnMajorNotRowMajor) {
  // A horizontal 3-pixel line in a 3x3 image: column-major runs are
  // 1,1,2,1,2,1,1.
  std::vector<uint32_t> ids = {0, 0, 0, 7, 7, 7, 0, 0, 0};
  EXPECT_EQ(CocoRleCounts(MaskOf(ids, 3, 3, 7)), (std::vector<uint32_t>{1, 1, 2, 1, 2, 1, 1}));
  // CVAT: row-major inside the tight box (1 row of 3): no background, one run
  // of 3.
  EXPECT_EQ(CvatRleCounts(MaskOf(ids, 3, 3, 7)), (std::vector<uint32_t>{0, 3}));
}

TEST(CocoRle, SinglePixelAndBorderObjects) {
  const int w = 7, h = 5;
  for (int y : {0, 2, h - 1}) {
    for (int x : {0, 3, w - 1}) {
      std::vector<uint32_t> ids(w * h, 0);
      ids[y * w + x] = 9;
      ExpectRoundTrips(ids, w, h, 9);
    }
  }
  std::vector<uint32_t> full(w * h, 4);  // the whole image
  ExpectRoundTrips(full, w, h, 4);
  ExpectRoundTrips(full, w, h, 3);  // absent: one background run
}

TEST(CocoRle, RandomMasksRoundTrip) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 200; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 40), h = 1 + static_cast<int>(rng() % 40);
    std::vector<uint32_t> ids(w * h);
    // Blobs of a few ids, some pixels noise: several pieces, holes, border
    // contact.
    for (uint32_t& id : ids) id = rng() % 5;  // 0 is background
    for (uint32_t id = 1; id <= 4; ++id) ExpectRoundTrips(ids, w, h, id);
  }
}

TEST(Polygons, InsideTheBoxAndCoverTheMask) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 100; ++trial) {
    const int w = 2 + static_cast<int>(rng() % 30), h = 2 + static_cast<int>(rng() % 30);
    std::vector<uint32_t> ids(w * h);
    for (uint32_t& id : ids) id = (rng() % 3 == 0) ? 1 : 0;
    const BoxMask mask = MaskOf(ids, w, h, 1);
    if (mask.empty()) continue;
    const MaskPolygons polygons = ExtractPolygons(mask);
    ASSERT_FALSE(polygons.pieces.empty());
    for (const Polygon& polygon : polygons.pieces) {
      EXPECT_GE(polygon.size(), 3u);
      for (const cv::Point2d& p : polygon) {
        EXPECT_GE(p.x, mask.left);
        EXPECT_LE(p.x, mask.left + mask.width());
        EXPECT_GE(p.y, mask.top);
        EXPECT_LE(p.y, mask.top + mask.height());
      }
    }
    // The merged polygon holds every piece's vertices.
    const Polygon merged = MergePieces(polygons.pieces);
    size_t vertices = 0;
    for (const Polygon& polygon : polygons.pieces) vertices += polygon.size();
    EXPECT_EQ(merged.size(), vertices + 2 * (polygons.pieces.size() - 1));
  }
}

TEST(Polygons, SinglePixelIsItsSquare) {
  std::vector<uint32_t> ids(5 * 4, 0);
  ids[2 * 5 + 4] = 1;  // pixel (4, 2), at the right border
  const MaskPolygons polygons = ExtractPolygons(MaskOf(ids, 5, 4, 1));
  ASSERT_EQ(polygons.pieces.size(), 1u);
  const Polygon expected = {{4, 2}, {5, 2}, {5, 3}, {4, 3}};
  EXPECT_EQ(polygons.pieces[0], expected);
}

TEST(Polygons, PiecesAndHolesAreCounted) {
  // A 5x5 ring (one hole) and a separate pixel: two pieces, one hole.
  const int w = 9, h = 7;
  std::vector<uint32_t> ids(w * h, 0);
  for (int y = 1; y <= 5; ++y) {
    for (int x = 1; x <= 5; ++x) ids[y * w + x] = (x == 3 && y == 3) ? 0 : 2;
  }
  ids[3 * w + 7] = 2;
  const MaskPolygons polygons = ExtractPolygons(MaskOf(ids, w, h, 2));
  EXPECT_EQ(polygons.pieces.size(), 2u);
  EXPECT_EQ(polygons.holes, 1);
  // Largest first: the ring's outer boundary along its pixel edges.
  const Polygon ring = {{1, 1}, {6, 1}, {6, 6}, {1, 6}};
  EXPECT_EQ(polygons.pieces[0], ring);
}

// pycocotools' own rule (frPyObjects + decode, rleFrPoly ported in
// reference_decoders.h) applied to the written polygons gives back the mask
// with its holes filled: exactly the mask when it has no holes.
cv::Mat CocoRasterized(const MaskPolygons& polygons, int w, int h) {
  std::vector<std::vector<double>> flat;
  for (const Polygon& polygon : polygons.pieces) {
    flat.emplace_back();
    for (const cv::Point2d& p : polygon) {
      flat.back().push_back(p.x);
      flat.back().push_back(p.y);
    }
  }
  return testing::CocoPolygonsToMask(flat, h, w);
}

cv::Mat HolesFilled(const cv::Mat& mask01) {
  cv::Mat padded;
  cv::copyMakeBorder(mask01, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
  cv::floodFill(padded, cv::Point(0, 0), 2, nullptr, 0, 0, 4);
  cv::Mat filled = padded != 2;
  return filled(cv::Rect(1, 1, mask01.cols, mask01.rows)) / 255;
}

void ExpectCocoExact(const std::vector<uint32_t>& ids, int w, int h) {
  const MaskPolygons polygons = ExtractPolygons(MaskOf(ids, w, h, 1));
  const cv::Mat expected = HolesFilled(FullMask(ids, w, h, 1));
  const cv::Mat got = CocoRasterized(polygons, w, h);
  EXPECT_EQ(cv::countNonZero(got != expected), 0)
      << "pycocotools rasterizes " << cv::countNonZero(got) << " pixels for "
      << cv::countNonZero(expected);
}

std::vector<uint32_t> Shape(int w, int h, const std::vector<cv::Point>& on) {
  std::vector<uint32_t> ids(w * h, 0);
  for (const cv::Point& p : on) ids[p.y * w + p.x] = 1;
  return ids;
}

TEST(PolygonsPycocotools, SinglePixelIsExact) {
  ExpectCocoExact(Shape(5, 4, {{0, 0}}), 5, 4);
  ExpectCocoExact(Shape(5, 4, {{4, 3}}), 5, 4);
  ExpectCocoExact(Shape(5, 4, {{2, 1}}), 5, 4);
}

TEST(PolygonsPycocotools, LShapeIsExact) {
  ExpectCocoExact(Shape(6, 6, {{1, 1}, {1, 2}, {1, 3}, {2, 3}, {3, 3}}), 6, 6);
}

TEST(PolygonsPycocotools, DiagonalStaircaseIsExact) {
  // Pixels touching only at corners: one 8-connected piece.
  ExpectCocoExact(Shape(6, 6, {{0, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}}), 6, 6);
  ExpectCocoExact(Shape(6, 6, {{4, 0}, {3, 1}, {2, 2}, {1, 3}, {0, 4}}), 6, 6);
  // A two-pixel-thick staircase.
  ExpectCocoExact(Shape(6, 6, {{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {3, 2}, {3, 3}}), 6, 6);
}

TEST(PolygonsPycocotools, DiscIsExact) {
  const int w = 40, h = 36;
  cv::Mat disc = cv::Mat::zeros(h, w, CV_8U);
  cv::circle(disc, {19, 17}, 13, 1, cv::FILLED);
  std::vector<uint32_t> ids(w * h);
  for (int i = 0; i < w * h; ++i) ids[i] = disc.data[i];
  const MaskPolygons polygons = ExtractPolygons(MaskOf(ids, w, h, 1));
  ASSERT_EQ(polygons.pieces.size(), 1u);
  EXPECT_EQ(polygons.holes, 0);
  ExpectCocoExact(ids, w, h);
}

TEST(PolygonsPycocotools, RandomMasksAreExactUpToFilledHoles) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 30), h = 1 + static_cast<int>(rng() % 30);
    std::vector<uint32_t> ids(w * h);
    for (uint32_t& id : ids) id = (rng() % 3 == 0) ? 1 : 0;
    if (std::count(ids.begin(), ids.end(), 1u) == 0) continue;
    ExpectCocoExact(ids, w, h);
  }
}

TEST(PolygonsUltralytics, SegmentBoxIsThePixelEdgeBox) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 30), h = 1 + static_cast<int>(rng() % 30);
    std::vector<uint32_t> ids(w * h);
    for (uint32_t& id : ids) id = (rng() % 4 == 0) ? 1 : 0;
    const BoxMask mask = MaskOf(ids, w, h, 1);
    if (mask.empty()) continue;
    const Polygon merged = MergePieces(ExtractPolygons(mask).pieces);
    const cv::Rect2d box = testing::UltralyticsSegmentToBox(merged, w, h);
    EXPECT_EQ(box, cv::Rect2d(mask.left, mask.top, mask.width(), mask.height()));
  }
}

// Ultralytics' own rule (ultralytics/data/utils.py, polygon2mask): the label
// values, float32, times the image size, cast to int32, filled by
// cv2.fillPoly with the boundary. Each piece's inset polygon, written with 6
// decimals as yolo-seg writes it, gives back that piece with its holes filled.
cv::Mat UltralyticsRasterized(const MaskPolygons& polygons, int w, int h) {
  cv::Mat out = cv::Mat::zeros(h, w, CV_8U);
  for (const Polygon& polygon : polygons.pieces) {
    std::vector<cv::Point> points;
    for (const cv::Point2d& p : polygon) {
      const float x = std::stof(cv::format("%.6f", p.x / w));
      const float y = std::stof(cv::format("%.6f", p.y / h));
      points.emplace_back(static_cast<int32_t>(x * static_cast<float>(w)),
                          static_cast<int32_t>(y * static_cast<float>(h)));
    }
    cv::Mat piece = cv::Mat::zeros(h, w, CV_8U);
    cv::fillPoly(piece, std::vector<std::vector<cv::Point>>{points}, 1);
    out |= piece;
  }
  return out;
}

void ExpectUltralyticsExact(const std::vector<uint32_t>& ids, int w, int h) {
  const MaskPolygons polygons =
      ExtractPolygons(MaskOf(ids, w, h, 1), PolygonVertices::kInsetCorners);
  const cv::Mat expected = HolesFilled(FullMask(ids, w, h, 1));
  const cv::Mat got = UltralyticsRasterized(polygons, w, h);
  EXPECT_EQ(cv::countNonZero(got != expected), 0)
      << "polygon2mask rasterizes " << cv::countNonZero(got) << " pixels for "
      << cv::countNonZero(expected);
}

TEST(PolygonsUltralytics, InsetCornersAreExactOnShapes) {
  ExpectUltralyticsExact(Shape(5, 4, {{0, 0}}), 5, 4);
  ExpectUltralyticsExact(Shape(5, 4, {{4, 3}}), 5, 4);
  ExpectUltralyticsExact(Shape(6, 6, {{1, 1}, {1, 2}, {1, 3}, {2, 3}, {3, 3}}), 6, 6);
  ExpectUltralyticsExact(Shape(6, 6, {{0, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}}), 6, 6);
  ExpectUltralyticsExact(Shape(6, 6, {{4, 0}, {3, 1}, {2, 2}, {1, 3}, {0, 4}}), 6, 6);
  ExpectUltralyticsExact(
      Shape(6, 6, {{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {3, 2}, {3, 3}}), 6, 6);
  const int w = 40, h = 36;
  cv::Mat disc = cv::Mat::zeros(h, w, CV_8U);
  cv::circle(disc, {19, 17}, 13, 1, cv::FILLED);
  std::vector<uint32_t> ids(w * h);
  for (int i = 0; i < w * h; ++i) ids[i] = disc.data[i];
  ExpectUltralyticsExact(ids, w, h);
}

TEST(PolygonsUltralytics, InsetCornersAreExactOnRandomMasks) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 300; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 30), h = 1 + static_cast<int>(rng() % 30);
    std::vector<uint32_t> ids(w * h);
    for (uint32_t& id : ids) id = (rng() % 3 == 0) ? 1 : 0;
    if (std::count(ids.begin(), ids.end(), 1u) == 0) continue;
    ExpectUltralyticsExact(ids, w, h);
  }
}

// The inset outlasts 6-decimal rounding and float32 on a wide image: an
// object at the far right of a 25,000-pixel-wide frame.
TEST(PolygonsUltralytics, InsetCornersAreExactOnAWideImage) {
  const int w = 25000, h = 3;
  ExpectUltralyticsExact(Shape(w, h, {{w - 1, 0}, {w - 2, 1}, {w - 3, 1}, {12345, 2}}), w, h);
}

TEST(PolygonsUltralytics, InsetSegmentBoxIsThePixelEdgeBox) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 30), h = 1 + static_cast<int>(rng() % 30);
    std::vector<uint32_t> ids(w * h);
    for (uint32_t& id : ids) id = (rng() % 4 == 0) ? 1 : 0;
    const BoxMask mask = MaskOf(ids, w, h, 1);
    if (mask.empty()) continue;
    const Polygon merged =
        MergePieces(ExtractPolygons(mask, PolygonVertices::kInsetCorners).pieces);
    const cv::Rect2d box = testing::UltralyticsSegmentToBox(merged, w, h);
    EXPECT_NEAR(box.x, mask.left, kCornerInset + 1e-12);
    EXPECT_NEAR(box.y, mask.top, kCornerInset + 1e-12);
    EXPECT_NEAR(box.x + box.width, mask.left + mask.width(), kCornerInset + 1e-9);
    EXPECT_NEAR(box.y + box.height, mask.top + mask.height(), kCornerInset + 1e-9);
  }
}

}  // namespace
}  // namespace lsds::masks

namespace lsds::masks {
namespace {

// The reading side of COCO RLE against pycocotools' own (_mask.frPoly, area,
// toBbox, iou, merge at cocodataset/cocoapi 8c9bcc3, run once on these three
// polygons of a 12 x 10 image; the strings and numbers below are its output).
const std::vector<std::vector<double>> kPolygons = {
    {1.2, 2.7, 9.6, 3.1, 7.3, 11.8},
    {0, 0, 10, 0, 10, 5, 0, 5},
    {-2.5, 3.3, 6.1, -1.2, 14.9, 8.8, 3.3, 12.6, 0.4, 7.7}};

TEST(CocoRleReading, PolygonsRasteriseAsFrPolyDoes) {
  const char* expected[] = {"k02:1O1O2N1O1OL=", "057000000000000000000", "2652O2Ma11_N2NM"};
  const uint64_t areas[] = {34, 50, 101};
  const std::array<double, 4> boxes[] = {{2, 3, 7, 8}, {0, 0, 10, 5}, {0, 0, 10, 12}};
  for (size_t i = 0; i < kPolygons.size(); ++i) {
    const CocoRle rle = CocoRleFromPolygon(kPolygons[i], 12, 10);
    EXPECT_EQ(CocoRleToString(rle.counts), expected[i]) << i;
    EXPECT_EQ(CocoRleArea(rle.counts), areas[i]) << i;
    EXPECT_EQ(CocoRleBox(rle), boxes[i]) << i;
    std::vector<uint32_t> decoded;
    ASSERT_TRUE(CocoRleFromString(expected[i], &decoded)) << i;
    EXPECT_EQ(decoded, rle.counts) << i;
  }
}

TEST(CocoRleReading, IouAndUnionAreThoseOfMaskApi) {
  std::vector<CocoRle> rles;
  for (const auto& p : kPolygons) rles.push_back(CocoRleFromPolygon(p, 12, 10));
  EXPECT_DOUBLE_EQ(CocoRleIou(rles[0], rles[1], false), 0.2);
  EXPECT_DOUBLE_EQ(CocoRleIou(rles[0], rles[2], true), 1.0);  // crowd: over the detection's area
  const CocoRle merged = CocoRleUnion({rles[0], rles[1]});
  EXPECT_EQ(CocoRleToString(merged.counts), "05700001O1O2N1O1OL4N2");
  EXPECT_EQ(CocoRleArea(merged.counts), 70u);
}

TEST(CocoRleReading, StringsTheCocoApiCannotDecodeAreRefused) {
  std::vector<uint32_t> counts;
  EXPECT_FALSE(CocoRleFromString("0 5", &counts));  // ' ' is below '0'
  EXPECT_FALSE(CocoRleFromString("05p", &counts));  // 'p' is above 'o'
  EXPECT_FALSE(CocoRleFromString("0h", &counts));   // ends inside a count (continuation bit)
  EXPECT_FALSE(CocoRleFromString("01O", &counts));  // 1 - 2: a negative run
  EXPECT_TRUE(CocoRleFromString("", &counts));
  EXPECT_TRUE(counts.empty());
}

}  // namespace
}  // namespace lsds::masks
