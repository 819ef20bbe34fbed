// COCO instances JSON (docs/convert.md): annotations/instances_<split>.json per
// split.
#pragma once

#include <memory>

#include "converters/converter.h"

namespace lsds::convert {

std::unique_ptr<Converter> MakeCocoConverter();

}  // namespace lsds::convert
