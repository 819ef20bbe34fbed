// The label line of one instance in Ultralytics' segmentation format
// (`yolo-seg`, docs/convert.md), with the pixels Ultralytics' own rasterizer
// would get wrong counted into the loss report.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "converters/loss_report.h"
#include "libs/masks/instance_masks.h"

namespace lsds::convert {

// "cls x1 y1 x2 y2 ..." normalized by the image size with 6 decimals: one
// polygon per instance (pieces bridged, holes filled), its vertices inset
// from the pixel corners (masks::PolygonVertices::kInsetCorners) so that
// Ultralytics' polygon2mask gives back the mask. Values outside [0, 1] are
// clipped and counted in `clipped`.
std::string YoloSegmentLine(int class_index,
                            const std::string& class_name,
                            const masks::BoxMask& mask,
                            LossReport* loss,
                            int* clipped);

// Ultralytics' rasterization of a label line's coordinates
// (ultralytics/data/utils.py, polygon2mask: the label values are float32,
// multiplied by the image size, cast to int32, then drawn by cv2.fillPoly,
// boundary included): the window `region` of that image, CV_8U, 1 inside.
cv::Mat UltralyticsPolygonMask(const std::vector<float>& normalized_xy,
                               int width,
                               int height,
                               const cv::Rect& region);

}  // namespace lsds::convert
