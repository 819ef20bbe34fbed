#include "report/draw.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace lsds::report {

namespace {

// HSV (h in [0, 1)) to BGR bytes.
cv::Vec3b HsvToBgr(double h, double s, double v) {
  const double i = std::floor(h * 6);
  const double f = h * 6 - i;
  const double p = v * (1 - s), q = v * (1 - f * s), t = v * (1 - (1 - f) * s);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(i) % 6) {
    case 0:
      r = v, g = t, b = p;
      break;
    case 1:
      r = q, g = v, b = p;
      break;
    case 2:
      r = p, g = v, b = t;
      break;
    case 3:
      r = p, g = q, b = v;
      break;
    case 4:
      r = t, g = p, b = v;
      break;
    default:
      r = v, g = p, b = q;
      break;
  }
  return cv::Vec3b(static_cast<uchar>(std::lround(b * 255)),
                   static_cast<uchar>(std::lround(g * 255)),
                   static_cast<uchar>(std::lround(r * 255)));
}

// Hues from the golden ratio sequence, so that neighbouring ids differ.
cv::Vec3b SequenceColor(uint32_t n, double saturation) {
  const double hue = std::fmod(0.11 + n * 0.6180339887498949, 1.0);
  const uint32_t h = n * 2654435761u;  // a little jitter in value per id
  return HsvToBgr(hue, saturation, 0.8 + 0.2 * ((h >> 16) & 255) / 255.0);
}

}  // namespace

cv::Vec3b IdColor(uint32_t id) {
  if (id == 0) return cv::Vec3b(0, 0, 0);
  return SequenceColor(id, 0.85);
}

cv::Vec3b ClassColor(uint32_t class_id) { return SequenceColor(class_id * 7 + 3, 1.0); }

cv::Rect PixelRect(const Box2d& box, double scale, const cv::Size& image) {
  const int x0 = static_cast<int>(std::lround(box.x0 * scale));
  const int y0 = static_cast<int>(std::lround(box.y0 * scale));
  const int x1 = std::max(x0 + 1, static_cast<int>(std::lround(box.x1 * scale)));
  const int y1 = std::max(y0 + 1, static_cast<int>(std::lround(box.y1 * scale)));
  return cv::Rect(x0, y0, x1 - x0, y1 - y0) & cv::Rect(0, 0, image.width, image.height);
}

void DrawBox(cv::Mat* bgr, const Box2d& box, double scale, const cv::Vec3b& color) {
  const cv::Rect r = PixelRect(box, scale, bgr->size());
  if (r.empty()) return;
  // cv::rectangle's corners are inclusive pixel positions.
  cv::rectangle(*bgr,
                r.tl(),
                cv::Point(r.x + r.width - 1, r.y + r.height - 1),
                cv::Scalar(color[0], color[1], color[2]),
                1,
                cv::LINE_8);
}

void DrawAnnotations(cv::Mat* bgr,
                     const CollectionHeader& header,
                     const Frame& frame,
                     const exr::FlatImage* instance_ids,
                     const AnnotateOptions& options) {
  // The id image at the drawing's size (nearest neighbour keeps ids whole).
  cv::Mat ids;
  if (options.outlines && instance_ids != nullptr && instance_ids->Find("id") != nullptr) {
    const std::vector<uint32_t>& values = instance_ids->Get("id").uints;
    cv::Mat full(instance_ids->height(),
                 instance_ids->width(),
                 CV_32S,
                 const_cast<uint32_t*>(values.data()));
    if (full.size() == bgr->size()) {
      ids = full;
    } else {
      cv::resize(full, ids, bgr->size(), 0, 0, cv::INTER_NEAREST);
    }
  }
  for (const ObjectTruth& object : frame.objects) {
    if (object.visible_pixels <= 0 || !object.bbox) continue;
    if (ids.empty()) break;
    // Look one pixel around the box: rounding may move the mask a little.
    cv::Rect roi = PixelRect(*object.bbox, options.scale, bgr->size());
    roi = cv::Rect(roi.x - 1, roi.y - 1, roi.width + 2, roi.height + 2) &
          cv::Rect(0, 0, ids.cols, ids.rows);
    if (roi.empty()) continue;
    cv::Mat mask = ids(roi) == static_cast<int>(object.instance_id);
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(mask, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE, roi.tl());
    const cv::Vec3b c = IdColor(object.instance_id);
    cv::drawContours(*bgr, contours, -1, cv::Scalar(c[0], c[1], c[2]), 1, cv::LINE_8);
  }
  for (const ObjectTruth& object : frame.objects) {
    if (object.visible_pixels <= 0 || !object.bbox || !options.boxes) continue;
    DrawBox(bgr, *object.bbox, options.scale, ClassColor(object.class_id));
  }
  if (!options.labels) return;
  for (const ObjectTruth& object : frame.objects) {
    if (object.visible_pixels <= 0 || !object.bbox) continue;
    const ClassInfo* info = header.FindClass(object.class_id);
    const std::string text = info ? info->name : "class " + std::to_string(object.class_id);
    const cv::Rect r = PixelRect(*object.bbox, options.scale, bgr->size());
    if (r.empty()) continue;
    int baseline = 0;
    const double font = 0.35;
    const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, font, 1, &baseline);
    // Above the box when there is room, else just inside its top edge.
    const int top = r.y - size.height - 3 >= 0 ? r.y - size.height - 3 : r.y + 1;
    const cv::Rect label =
        cv::Rect(r.x, top, size.width + 2, size.height + 3) & cv::Rect(0, 0, bgr->cols, bgr->rows);
    if (label.empty()) continue;
    // A translucent tag: small objects under it stay visible.
    const cv::Vec3b c = ClassColor(object.class_id);
    cv::Mat tag = (*bgr)(label);
    cv::addWeighted(
        tag, 0.45, cv::Mat(tag.size(), tag.type(), cv::Scalar(c[0], c[1], c[2])), 0.55, 0.0, tag);
    cv::putText(*bgr,
                text,
                cv::Point(r.x + 1, top + size.height + 1),
                cv::FONT_HERSHEY_SIMPLEX,
                font,
                cv::Scalar(0, 0, 0),
                1,
                cv::LINE_AA);
  }
}

}  // namespace lsds::report
