// Ultralytics YOLO detection (`yolo`), segmentation (`yolo-seg`) and
// oriented-box (`yolo-obb`) labels (docs/convert.md): one converter, so the
// three share data.yaml, the label folders and the class names.
#pragma once

#include <memory>

#include "converters/converter.h"

namespace lsds::convert {

enum class YoloTask { kDetect, kSegment, kOriented };

std::unique_ptr<Converter> MakeYoloConverter(YoloTask task);

// One label line: "cls xc yc w h" normalized by the image size, each value
// clipped to [0, 1] (the count of clipped values is returned through
// `clipped`), 6 decimals.
std::string YoloBoxLine(int class_index, const Box2d& box, int width, int height, int* clipped);

// One OBB label line: "cls x1 y1 x2 y2 x3 y3 x4 y4", the corners of `box`
// (pixel-edge, in its order) divided by the image size, 6 decimals. A box
// reaching out of the image is cut to it first (ClippedTo: the minimum-area
// rectangle of the clipped polygon), then every value is clamped to [0, 1];
// `clipped` is set when either changed anything.
std::string YoloObbLine(
    int class_index, const OrientedBox2d& box, int width, int height, bool* clipped);

}  // namespace lsds::convert
