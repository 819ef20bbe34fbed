// Checks of oriented-box exports shared by the dota / yolo-obb tests: each
// label file read with the consumers' rules (obb_consumers.h) and each box
// against its object's instance mask (covers every pixel; the area of
// OpenCV's minimum-area rectangle of the mask, an implementation independent
// of lsds').
#pragma once

#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "converters/dota/dota_converter.h"
#include "libs/collection/rig.h"
#include "tests/convert/convert_test_util.h"
#include "tests/convert/obb_consumers.h"

namespace lsds::testing {

using Corners = std::array<cv::Point2d, 4>;

// Pixel-edge corners of every pixel of a mask.
inline std::vector<cv::Point2d> PixelCorners(const cv::Mat& mask) {
  std::vector<cv::Point2d> points;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (mask.at<uint8_t>(y, x))
        points.insert(
            points.end(),
            {{x * 1.0, y * 1.0}, {x + 1.0, y * 1.0}, {x * 1.0, y + 1.0}, {x + 1.0, y + 1.0}});
  return points;
}

// OpenCV's minimum-area rectangle of a mask's pixel squares (the rule
// MMRotate applies, cv2.minAreaRect): {shorter side, longer side}.
inline std::pair<double, double> CvSides(const cv::Mat& mask) {
  std::vector<cv::Point2f> points;
  for (const cv::Point2d& p : PixelCorners(mask)) points.emplace_back(float(p.x), float(p.y));
  const cv::RotatedRect r = cv::minAreaRect(points);
  return {std::min(r.size.width, r.size.height), std::max(r.size.width, r.size.height)};
}

inline double SignedArea(const Corners& c) {
  double a = 0;
  for (int i = 0; i < 4; ++i) a += c[i].x * c[(i + 1) % 4].y - c[(i + 1) % 4].x * c[i].y;
  return a / 2;
}

// A rectangle: right angles and equal opposite sides, within `tolerance`
// pixels (the rounding of the written values), clockwise on the image.
inline void ExpectRectangle(const Corners& c, double tolerance, const std::string& where) {
  EXPECT_GT(SignedArea(c), 0) << where << ": not clockwise on the image (y down)";
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d a = c[(i + 1) % 4] - c[i], b = c[(i + 2) % 4] - c[(i + 1) % 4];
    EXPECT_LE(std::abs(a.dot(b)) / std::max(1e-9, cv::norm(a)), 2 * tolerance) << where;
  }
  EXPECT_NEAR(cv::norm(c[1] - c[0]), cv::norm(c[2] - c[3]), 2 * tolerance) << where;
  EXPECT_NEAR(cv::norm(c[2] - c[1]), cv::norm(c[3] - c[0]), 2 * tolerance) << where;
}

// Share of the mask's pixel corners inside the clockwise polygon `c`.
inline double Coverage(const Corners& c, const cv::Mat& mask, double tolerance) {
  const std::vector<cv::Point2d> points = PixelCorners(mask);
  int inside = 0;
  for (const cv::Point2d& p : points) {
    bool in = true;
    for (int i = 0; i < 4; ++i) {
      const cv::Point2d e = c[(i + 1) % 4] - c[i], d = p - c[i];
      if (e.x * d.y - e.y * d.x < -tolerance * cv::norm(e)) in = false;
    }
    inside += in;
  }
  return points.empty() ? 1.0 : double(inside) / points.size();
}

// Visible objects of a frame, in the frame's order, with their masks.
inline std::vector<std::pair<const ObjectTruth*, cv::Mat>> Visible(const fs::path& collection,
                                                                   const Frame& frame) {
  std::vector<std::pair<const ObjectTruth*, cv::Mat>> out;
  for (const ObjectTruth& o : frame.objects)
    if (o.bbox && o.visible_pixels > 0)
      out.emplace_back(&o, InstanceMask(collection, frame, o.instance_id));
  return out;
}

inline std::string ClassName(const fs::path& collection, uint32_t id) {
  const CollectionReader reader(collection);
  const ClassInfo* c = reader.header().FindClass(id);
  return c ? c->name : "";
}

struct DotaFindings {
  int lines = 0, under_size = 0, empty_images = 0;
};

// Every label file of a dota export (default options) read by the DOTA
// devkit's and MMRotate's rules, and each line against its object's mask.
inline DotaFindings CheckDota(const fs::path& collection, const fs::path& out) {
  DotaFindings found;
  std::set<std::string> names;
  const CollectionReader reader(collection);
  for (const ClassInfo& c : reader.header().classes) names.insert(convert::DotaClassName(c.name));
  for (const Frame& frame : Frames(collection)) {
    const std::string where = "labelTxt/train/" + FrameFileStem(frame) + ".txt";
    const std::string text = ReadText(out / where);
    std::string error;
    const std::vector<DevkitObject> devkit = DevkitParse(text, &error);
    EXPECT_EQ(error, "") << where;
    const MmrotateFile mmrotate = MmrotateLoad(text, names);
    EXPECT_FALSE(mmrotate.crashed) << where << ": " << mmrotate.error;
    EXPECT_EQ(mmrotate.dropped, 0) << where << ": MMRotate would drop a box";
    const std::vector<std::string> lines = Lines(text);
    EXPECT_EQ(devkit.size(), lines.size()) << where;
    // Expected lines: every visible object whose minimum-area rectangle has
    // both sides >= 2 px, in order.
    size_t next = 0;
    for (const auto& [object, mask] : Visible(collection, frame)) {
      const auto [short_side, long_side] = CvSides(mask);
      if (short_side < 2) {
        ++found.under_size;
        continue;
      }
      if (next >= lines.size()) {
        ADD_FAILURE() << where << ": fewer lines than objects";
        break;
      }
      const std::string& line = lines[next++];
      const std::vector<std::string> tokens = SplitSpace(line);
      if (tokens.size() != 10u) {
        ADD_FAILURE() << where << ": '" << line << "' has " << tokens.size() << " tokens";
        continue;
      }
      EXPECT_EQ(SplitWhitespace(line), tokens) << "whitespace other than single spaces";
      Corners c;
      for (int i = 0; i < 4; ++i) c[i] = {*PyFloat(tokens[2 * i]), *PyFloat(tokens[2 * i + 1])};
      ExpectRectangle(c, 0.01, where + ": " + line);
      EXPECT_EQ(Coverage(c, mask, 0.01), 1.0) << where << ": " << line;
      EXPECT_NEAR(std::abs(SignedArea(c)), short_side * long_side, 0.02 * long_side + 1e-3)
          << where << ": not the minimum-area rectangle";
      EXPECT_EQ(tokens[8], convert::DotaClassName(ClassName(collection, object->class_id)));
      const bool difficult = object->visibility < 0.5 || long_side < 15;
      EXPECT_EQ(tokens[9], difficult ? "1" : "0") << where << ": " << line;
      ++found.lines;
    }
    EXPECT_EQ(next, lines.size()) << where;
    if (lines.empty()) {
      ++found.empty_images;
      EXPECT_FALSE(MmrotateTrainsOn(mmrotate));
    }
  }
  return found;
}

// Every label file of a yolo-obb export read by Ultralytics' rules, and each
// line against its object's mask; returns the lines with a coordinate on the
// image border (clipped ones among them).
inline int CheckYoloObb(const fs::path& collection, const fs::path& out) {
  // data.yaml lists the names explicitly, in class order: the classes with a
  // visible object, by increasing id.
  std::set<uint32_t> used;
  for (const Frame& frame : Frames(collection))
    for (const ObjectTruth& o : frame.objects)
      if (o.bbox && o.visible_pixels > 0) used.insert(o.class_id);
  std::map<uint32_t, int> index;
  const std::string yaml = ReadText(out / "data.yaml");
  size_t at = yaml.find("names:\n");
  EXPECT_NE(at, std::string::npos) << yaml;
  for (uint32_t id : used) {
    const std::string entry =
        "\n  " + std::to_string(index.size()) + ": \"" + ClassName(collection, id) + "\"";
    at = yaml.find(entry, at);
    EXPECT_NE(at, std::string::npos) << entry << " in\n" << yaml;
    index[id] = static_cast<int>(index.size());
  }
  int border_lines = 0;
  for (const Frame& frame : Frames(collection)) {
    const std::string where = "labels/train/" + FrameFileStem(frame) + ".txt";
    EXPECT_TRUE(fs::exists(out / where)) << where;
    const std::string text = ReadText(out / where);
    const UltralyticsLabel label = UltralyticsVerify(text, static_cast<int>(index.size()));
    EXPECT_FALSE(label.dropped) << where << ": " << label.error;
    EXPECT_EQ(label.duplicates, 0) << where;
    const std::vector<std::string> lines = Lines(text);
    const auto visible = Visible(collection, frame);
    EXPECT_EQ(lines.size(), visible.size()) << where;
    const double w = frame.camera.intrinsics.width, h = frame.camera.intrinsics.height;
    for (size_t k = 0; k < std::min(lines.size(), visible.size()); ++k) {
      const std::vector<std::string> t = SplitWhitespace(lines[k]);
      if (t.size() != 9u) {
        ADD_FAILURE() << where << ": '" << lines[k] << "' has " << t.size() << " columns";
        continue;
      }
      EXPECT_EQ(t[0], std::to_string(index.at(visible[k].first->class_id)));
      Corners c;
      bool on_border = false;
      for (int i = 0; i < 4; ++i) {
        const double x = *PyFloat(t[1 + 2 * i]), y = *PyFloat(t[2 + 2 * i]);
        EXPECT_TRUE(x >= 0 && x <= 1 && y >= 0 && y <= 1) << where << ": " << lines[k];
        on_border = on_border || x == 0 || x == 1 || y == 0 || y == 1;
        c[i] = {x * w, y * h};
      }
      const double coverage = Coverage(c, visible[k].second, 1e-3);
      if (!on_border) {
        ExpectRectangle(c, 1e-3, where + ": " + lines[k]);
        EXPECT_EQ(coverage, 1.0) << where << ": " << lines[k];
      } else {
        // An object cut by the border: the rectangle of the clipped polygon,
        // clamped into the image, still holds nearly all of the mask.
        ++border_lines;
        EXPECT_GE(coverage, 0.9) << where << ": " << lines[k];
      }
    }
  }
  return border_lines;
}

}  // namespace lsds::testing
