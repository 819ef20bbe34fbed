// Truth drawn onto display images: tight boxes, instance mask outlines and
// class names, with a stable colour per id (docs/report.md).
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "libs/collection/model.h"
#include "libs/exr/flat_image.h"

namespace lsds::report {

// A stable, well-saturated BGR colour per id; id 0 (background) is black.
cv::Vec3b IdColor(uint32_t id);
// The colour of a class (a different sequence from instances).
cv::Vec3b ClassColor(uint32_t class_id);

// The pixel rectangle a pixel-edge box covers on an image drawn at `scale`
// (image pixels per collection pixel): edges rounded to the nearest pixel edge,
// at least one pixel wide, clipped to `bgr`. Empty when outside.
cv::Rect PixelRect(const Box2d& box, double scale, const cv::Size& image);

// Paints the one-pixel outline of PixelRect(box): its first and last rows and
// columns, nothing else. At scale 1 those are the pixels just inside the box's
// edges x0, x1, y0, y1.
void DrawBox(cv::Mat* bgr, const Box2d& box, double scale, const cv::Vec3b& color);

struct AnnotateOptions {
  double scale = 1.0;  // `bgr` pixels per collection pixel
  bool outlines = true;
  bool boxes = true;
  bool labels = true;
};

// Draws every visible object of `frame` onto `bgr` (the frame's image at
// `scale`): mask outlines from `instance_ids` (channel "id", collection
// resolution; skipped when null) in the instance's colour, then the tight box
// in the class colour, then the class name above the box.
void DrawAnnotations(cv::Mat* bgr,
                     const CollectionHeader& header,
                     const Frame& frame,
                     const exr::FlatImage* instance_ids,
                     const AnnotateOptions& options);

}  // namespace lsds::report
