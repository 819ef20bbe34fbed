#include "converters/yolo/yolo_segment.h"

#include <algorithm>
#include <cstdlib>

#include <opencv2/imgproc.hpp>

#include "converters/format_util.h"
#include "libs/masks/contours.h"

namespace lsds::convert {

std::string YoloSegmentLine(int class_index,
                            const std::string& class_name,
                            const masks::BoxMask& mask,
                            LossReport* loss,
                            int* clipped) {
  const masks::MaskPolygons polygons =
      masks::ExtractPolygons(mask, masks::PolygonVertices::kInsetCorners);
  if (polygons.pieces.size() > 1) loss->Add(loss::kPiecesMerged, class_name);
  if (polygons.holes > 0) loss->Add(loss::kHolesFilled, class_name);
  loss->Add(loss::kPolygonMaskPixels, class_name, mask.pixel_count);
  loss->Add(loss::kPolygonHolePixels, class_name, polygons.hole_pixels);
  std::string line = std::to_string(class_index);
  std::vector<float> written;  // what Ultralytics will read back
  for (const cv::Point2d& p : masks::MergePieces(polygons.pieces)) {
    for (const double v : {p.x / mask.image_width, p.y / mask.image_height}) {
      const double inside = std::clamp(v, 0.0, 1.0);
      if (inside != v) ++*clipped;
      const std::string text = Format(" %.6f", inside);
      line += text;
      written.push_back(std::strtof(text.c_str(), nullptr));
    }
  }
  // Holes and the bridges between pieces are filled by any polygon
  // rasterizer; count every pixel that differs from the instance mask.
  const cv::Rect box(mask.left, mask.top, mask.width(), mask.height());
  const cv::Mat rasterized =
      UltralyticsPolygonMask(written, mask.image_width, mask.image_height, box);
  const int64_t wrong = cv::countNonZero((mask.mask != 0) != (rasterized != 0));
  if (wrong > 0) {
    loss->Add(loss::kPolygon2maskObjects, class_name);
    loss->Add(loss::kPolygon2maskPixels, class_name, wrong);
  }
  return line + "\n";
}

cv::Mat UltralyticsPolygonMask(const std::vector<float>& normalized_xy,
                               int width,
                               int height,
                               const cv::Rect& region) {
  std::vector<cv::Point> points;
  for (size_t i = 0; i + 1 < normalized_xy.size(); i += 2) {
    // float32 products (the label array is float32), truncated toward zero.
    points.emplace_back(static_cast<int>(normalized_xy[i] * static_cast<float>(width)),
                        static_cast<int>(normalized_xy[i + 1] * static_cast<float>(height)));
  }
  cv::Mat mask = cv::Mat::zeros(region.height, region.width, CV_8U);
  if (!points.empty()) {
    cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{points}, 1, cv::LINE_8, 0, -region.tl());
  }
  return mask;
}

}  // namespace lsds::convert
