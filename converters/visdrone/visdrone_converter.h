// VisDrone2019 DET (one annotation file per image) and VID (one per sequence)
// ground truth (docs/convert.md, "visdrone", "visdrone-vid").
#pragma once

#include <memory>

#include "converters/converter.h"

namespace lsds::convert {

std::unique_ptr<Converter> MakeVisDroneConverter();
std::unique_ptr<Converter> MakeVisDroneVidConverter();

}  // namespace lsds::convert
