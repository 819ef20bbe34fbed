// CVAT for images 1.1 (`cvat`) and CVAT for video 1.1 (`cvat-video`) XML
// (docs/convert.md).
#pragma once

#include <memory>

#include "converters/converter.h"

namespace lsds::convert {

std::unique_ptr<Converter> MakeCvatImagesConverter();
std::unique_ptr<Converter> MakeCvatVideoConverter();

}  // namespace lsds::convert
