// Ultralytics YOLO detection (`yolo`) and segmentation (`yolo-seg`) labels
// (docs/convert.md).
#pragma once

#include <memory>

#include "converters/converter.h"

namespace lsds::convert {

std::unique_ptr<Converter> MakeYoloConverter(bool segmentation);

// One label line: "cls xc yc w h" normalized by the image size, each value
// clipped to [0, 1] (the count of clipped values is returned through
// `clipped`), 6 decimals.
std::string YoloBoxLine(int class_index, const Box2d& box, int width, int height, int* clipped);

}  // namespace lsds::convert
