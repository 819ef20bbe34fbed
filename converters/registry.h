// The registry of target formats: one line per format in registry.cc.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "converters/converter.h"

namespace lsds::convert {

// yolo, yolo-seg, yolo-obb, dota, coco, cvat, cvat-video, mot, visdrone, visdrone-vid
std::vector<std::string> ConverterNames();
// Throws lsds::Error for an unknown name.
std::unique_ptr<Converter> MakeConverter(const std::string& name);

}  // namespace lsds::convert
