// 2D oriented boxes (libs/geometry/oriented_box2d.h) against independent rules:
// a brute-force search over angles for the minimum area, pixel-square
// coverage, the shoelace sign for the corner order, and the heading corner's
// definition (on the front edge, left of the heading; y down).
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "libs/geometry/oriented_box2d.h"
#include "tests/libs/brute_force_rectangle.h"

namespace lsds {
namespace {

using testing::BruteForceMinimumArea;

constexpr double kPi = 3.14159265358979323846;

// Twice the signed area by the shoelace formula in image coordinates: positive
// when the corners run clockwise as seen on the image (x right, y down).
double ShoelaceOnImage(const OrientedBox2d& box) {
  double sum = 0;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d& a = box.corners[i];
    const Eigen::Vector2d& b = box.corners[(i + 1) % 4];
    sum += a.x() * b.y() - b.x() * a.y();
  }
  return sum;
}

// Consecutive sides perpendicular and opposite sides equal, to `tolerance`.
void ExpectRectangle(const OrientedBox2d& box, double tolerance = 1e-9) {
  const auto& c = box.corners;
  EXPECT_NEAR((c[1] - c[0]).dot(c[2] - c[1]), 0.0, tolerance * (1 + box.Area()));
  EXPECT_LE((c[0] + c[2] - c[1] - c[3]).norm(), tolerance * (1 + box.Width() + box.Height()));
}

// Corner 0 is the smallest in (y, x) order: the canonical first corner.
void ExpectCanonicalFirst(const OrientedBox2d& box) {
  for (int i = 1; i < 4; ++i) {
    const Eigen::Vector2d& first = box.corners[0];
    const Eigen::Vector2d& other = box.corners[i];
    EXPECT_TRUE(first.y() < other.y() || (first.y() == other.y() && first.x() <= other.x()))
        << "corner " << i << " (" << other.transpose() << ") comes before (" << first.transpose()
        << ")";
  }
}

struct IdLayer {
  int width, height;
  std::vector<uint32_t> ids;
  IdLayer(int w, int h) : width(w), height(h), ids(static_cast<size_t>(w) * h, 0) {}
  uint32_t& at(int x, int y) { return ids[static_cast<size_t>(y) * width + x]; }
  Box2d Whole() const { return {0, 0, static_cast<double>(width), static_cast<double>(height)}; }
  // The four corners of every pixel square holding `id`.
  std::vector<Eigen::Vector2d> PixelCorners(uint32_t id) const {
    std::vector<Eigen::Vector2d> corners;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        if (ids[static_cast<size_t>(y) * width + x] != id) continue;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) corners.emplace_back(x + dx, y + dy);
      }
    }
    return corners;
  }
};

TEST(MinimumAreaRectangle, AxisAlignedMaskGivesThePixelEdgeBoxExactly) {
  for (const Box2d& r : {Box2d{3, 4, 9, 6}, Box2d{0, 0, 5, 5}, Box2d{10, 1, 11, 19}}) {
    IdLayer layer(24, 24);
    for (int y = static_cast<int>(r.y0); y < r.y1; ++y)
      for (int x = static_cast<int>(r.x0); x < r.x1; ++x) layer.at(x, y) = 5;
    layer.at(20, 20) = 6;  // another instance does not count
    const auto box = MaskOrientedBox(layer.ids.data(), layer.width, layer.height, 5, layer.Whole());
    ASSERT_TRUE(box);
    // Clockwise on the image from the top-left corner.
    EXPECT_EQ(box->corners[0], Eigen::Vector2d(r.x0, r.y0));
    EXPECT_EQ(box->corners[1], Eigen::Vector2d(r.x1, r.y0));
    EXPECT_EQ(box->corners[2], Eigen::Vector2d(r.x1, r.y1));
    EXPECT_EQ(box->corners[3], Eigen::Vector2d(r.x0, r.y1));
    EXPECT_EQ(box->Bounds(), r);
  }
}

TEST(MinimumAreaRectangle, RasterizedRotatedRectangleIsCoveredWithMinimalArea) {
  for (double angle_deg : {0.0, 7.5, 30.0, 45.0, 63.2, 89.9, 121.0, 200.0}) {
    for (const Eigen::Vector2d& size : {Eigen::Vector2d(50.2, 17.6), Eigen::Vector2d(9.3, 4.1)}) {
      IdLayer layer(96, 96);
      const Eigen::Vector2d centre(47.3, 45.7);
      const double a = angle_deg * kPi / 180.0;
      const Eigen::Vector2d u(std::cos(a), std::sin(a)), v(-std::sin(a), std::cos(a));
      for (int y = 0; y < layer.height; ++y) {
        for (int x = 0; x < layer.width; ++x) {
          const Eigen::Vector2d d = Eigen::Vector2d(x + 0.5, y + 0.5) - centre;
          if (std::abs(d.dot(u)) <= size.x() / 2 && std::abs(d.dot(v)) <= size.y() / 2)
            layer.at(x, y) = 9;
        }
      }
      layer.at(0, 0) = 2;  // another instance
      const auto box =
          MaskOrientedBox(layer.ids.data(), layer.width, layer.height, 9, layer.Whole());
      ASSERT_TRUE(box);
      const std::vector<Eigen::Vector2d> corners = layer.PixelCorners(9);
      for (const Eigen::Vector2d& c : corners)
        ASSERT_TRUE(box->Contains(c, 1e-9))
            << "angle " << angle_deg << ": corner " << c.transpose();
      EXPECT_LE(box->Area(), BruteForceMinimumArea(corners) + 1e-9) << "angle " << angle_deg;
      ExpectRectangle(*box);
      EXPECT_GT(ShoelaceOnImage(*box), 0);
      ExpectCanonicalFirst(*box);
    }
  }
}

TEST(MinimumAreaRectangle, RandomPointSetsAgainstBruteForce) {
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> coordinate(-20.0, 60.0);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Eigen::Vector2d> points(3 + trial % 17);
    for (Eigen::Vector2d& p : points) p = {coordinate(rng), coordinate(rng)};
    const auto box = MinimumAreaRectangle(points);
    ASSERT_TRUE(box);
    for (const Eigen::Vector2d& p : points) EXPECT_TRUE(box->Contains(p, 1e-9));
    EXPECT_LE(box->Area(), BruteForceMinimumArea(points) + 1e-9) << "trial " << trial;
    ExpectRectangle(*box);
    EXPECT_GT(ShoelaceOnImage(*box), 0);
    ExpectCanonicalFirst(*box);
  }
}

TEST(MinimumAreaRectangle, SameResultWhateverThePointOrder) {
  std::vector<Eigen::Vector2d> points = {{1, 2}, {7, 3}, {4, 9}, {2, 6}, {6, 7}, {4, 4}, {1, 2}};
  const auto a = MinimumAreaRectangle(points);
  std::reverse(points.begin(), points.end());
  const auto b = MinimumAreaRectangle(points);
  ASSERT_TRUE(a && b);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(a->corners[i], b->corners[i]);
}

// Looking along `heading` on the image (y down), the left is (hy, -hx).
void ExpectHeadingCornerFirst(const OrientedBox2d& box, const Eigen::Vector2d& heading) {
  const Eigen::Vector2d mid = (box.corners[0] + box.corners[1]) / 2;
  const Eigen::Vector2d left(heading.y(), -heading.x());
  // Corners 0 and 1 form the front edge: the edge whose outward normal (from
  // the centre to its middle) makes the smallest angle with the heading.
  auto normal = [&](int i) {
    return ((box.corners[i] + box.corners[(i + 1) % 4]) / 2 - box.Center()).normalized();
  };
  for (int i = 1; i < 4; ++i) EXPECT_GT(normal(0).dot(heading), normal(i).dot(heading));
  EXPECT_GT((box.corners[0] - mid).dot(left), 0);
  EXPECT_GT(ShoelaceOnImage(box), 0);
}

TEST(WithHeadingCornerFirst, EachOfTheFourDirections) {
  const auto box = MinimumAreaRectangle({{2, 3}, {12, 3}, {12, 7}, {2, 7}});
  ASSERT_TRUE(box);
  struct Case {
    Eigen::Vector2d heading, first, second;
  };
  for (const Case& c : {Case{{1, 0}, {12, 3}, {12, 7}},     // right: front-left is the top
                        Case{{-1, 0}, {2, 7}, {2, 3}},      // left: front-left is the bottom
                        Case{{0, 1}, {12, 7}, {2, 7}},      // down the image: left is +x
                        Case{{0, -1}, {2, 3}, {12, 3}}}) {  // up the image: left is -x
    const OrientedBox2d turned = WithHeadingCornerFirst(*box, c.heading * 3.5);
    EXPECT_EQ(turned.corners[0], c.first) << "heading " << c.heading.transpose();
    EXPECT_EQ(turned.corners[1], c.second) << "heading " << c.heading.transpose();
    ExpectHeadingCornerFirst(turned, c.heading);
  }
}

TEST(WithHeadingCornerFirst, RotatedBoxAndObliqueHeadings) {
  const double a = 30 * kPi / 180.0;
  const Eigen::Vector2d u(std::cos(a), std::sin(a)), v(-std::sin(a), std::cos(a));
  const Eigen::Vector2d centre(50, 40);
  const auto box = MinimumAreaRectangle({centre + 8 * u + 3 * v,
                                         centre + 8 * u - 3 * v,
                                         centre - 8 * u + 3 * v,
                                         centre - 8 * u - 3 * v});
  ASSERT_TRUE(box);
  for (double turn_deg = 0; turn_deg < 360; turn_deg += 20) {
    const double t = a + turn_deg * kPi / 180.0;
    const Eigen::Vector2d heading(std::cos(t), std::sin(t));
    // 45 degrees off an axis is a tie between two edges; stay clear of it.
    if (std::abs(std::remainder(turn_deg, 90.0)) > 44) continue;
    ExpectHeadingCornerFirst(WithHeadingCornerFirst(*box, heading), heading);
  }
}

TEST(WithHeadingCornerFirst, ZeroHeadingKeepsTheCanonicalOrder) {
  const auto box = MinimumAreaRectangle({{2, 3}, {12, 3}, {12, 7}, {2, 7}});
  ASSERT_TRUE(box);
  const OrientedBox2d same = WithHeadingCornerFirst(*box, Eigen::Vector2d::Zero());
  for (int i = 0; i < 4; ++i) EXPECT_EQ(same.corners[i], box->corners[i]);
}

TEST(MaskOrientedBox, SinglePixel) {
  IdLayer layer(8, 8);
  layer.at(5, 2) = 1;
  const auto box = MaskOrientedBox(layer.ids.data(), 8, 8, 1, layer.Whole());
  ASSERT_TRUE(box);
  EXPECT_EQ(box->corners[0], Eigen::Vector2d(5, 2));
  EXPECT_EQ(box->corners[1], Eigen::Vector2d(6, 2));
  EXPECT_EQ(box->corners[2], Eigen::Vector2d(6, 3));
  EXPECT_EQ(box->corners[3], Eigen::Vector2d(5, 3));
  EXPECT_DOUBLE_EQ(box->Area(), 1.0);
}

TEST(MaskOrientedBox, OneRowAndOneColumn) {
  IdLayer layer(16, 16);
  for (int x = 3; x < 12; ++x) layer.at(x, 7) = 4;
  for (int y = 1; y < 15; ++y) layer.at(14, y) = 5;
  const auto row = MaskOrientedBox(layer.ids.data(), 16, 16, 4, layer.Whole());
  ASSERT_TRUE(row);
  EXPECT_EQ(row->Bounds(), (Box2d{3, 7, 12, 8}));
  EXPECT_DOUBLE_EQ(row->Area(), 9.0);
  const auto column = MaskOrientedBox(layer.ids.data(), 16, 16, 5, layer.Whole());
  ASSERT_TRUE(column);
  EXPECT_EQ(column->Bounds(), (Box2d{14, 1, 15, 15}));
  EXPECT_DOUBLE_EQ(column->Area(), 14.0);
}

TEST(MaskOrientedBox, OnlyPixelsInsideTheSearchBoxAndTheImage) {
  IdLayer layer(10, 10);
  layer.at(1, 1) = 3;
  layer.at(8, 8) = 3;
  // The window holds only (8, 8); it reaches past the image, which is clipped.
  const auto box = MaskOrientedBox(layer.ids.data(), 10, 10, 3, Box2d{5, 5, 40, 40});
  ASSERT_TRUE(box);
  EXPECT_EQ(box->Bounds(), (Box2d{8, 8, 9, 9}));
  EXPECT_FALSE(MaskOrientedBox(layer.ids.data(), 10, 10, 3, Box2d{2, 2, 7, 7}));
}

TEST(MaskOrientedBox, NoPixelOfTheIdGivesNothing) {
  IdLayer layer(6, 6);
  layer.at(2, 2) = 1;
  EXPECT_FALSE(MaskOrientedBox(layer.ids.data(), 6, 6, 2, layer.Whole()));
}

TEST(MinimumAreaRectangle, DegenerateInputs) {
  EXPECT_FALSE(MinimumAreaRectangle({}));
  // One point, repeated: all four corners on it.
  const auto point = MinimumAreaRectangle({{3, 4}, {3, 4}});
  ASSERT_TRUE(point);
  for (const Eigen::Vector2d& c : point->corners) EXPECT_EQ(c, Eigen::Vector2d(3, 4));
  EXPECT_EQ(point->Area(), 0.0);
  EXPECT_TRUE(point->Contains({3, 4}));
  EXPECT_FALSE(point->Contains({3, 4.1}, 0.05));
  // Collinear points: a rectangle of zero height from one end to the other.
  const auto line = MinimumAreaRectangle({{1, 1}, {3, 3}, {2, 2}, {5, 5}, {4, 4}});
  ASSERT_TRUE(line);
  EXPECT_NEAR(line->Area(), 0.0, 1e-12);
  // (Corners are rebuilt from the hull edge's direction: exact to rounding.)
  const Box2d bounds = line->Bounds();
  EXPECT_NEAR(bounds.x0, 1, 1e-12);
  EXPECT_NEAR(bounds.y0, 1, 1e-12);
  EXPECT_NEAR(bounds.x1, 5, 1e-12);
  EXPECT_NEAR(bounds.y1, 5, 1e-12);
  EXPECT_LE((line->corners[0] - Eigen::Vector2d(1, 1)).norm(), 1e-12);
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(1, 1), Eigen::Vector2d(2.5, 2.5), Eigen::Vector2d(5, 5)})
    EXPECT_TRUE(line->Contains(p, 1e-9)) << p.transpose();
  EXPECT_FALSE(line->Contains({2, 3}, 1e-3));
  EXPECT_FALSE(line->Contains({6, 6}, 1e-3));
  // Two points.
  const auto two = MinimumAreaRectangle({{4, 0}, {0, 3}});
  ASSERT_TRUE(two);
  EXPECT_NEAR(std::max(two->Width(), two->Height()), 5.0, 1e-12);
  EXPECT_LE((two->corners[0] - Eigen::Vector2d(4, 0)).norm(), 1e-12);
}

}  // namespace
}  // namespace lsds
