// Pieces shared by the CVAT for images and CVAT for video 1.1 writers.
#pragma once

#include <string>

#include "converters/class_map.h"
#include "libs/geometry/box2d.h"

namespace lsds::convert::cvat {

// <labels> with one <label> per output class (type "any", a fixed colour per
// index), indented.
std::string LabelsXml(const ClassMap& classes, const std::string& indent);
// xtl="..." ytl="..." xbr="..." ybr="..." in pixel-edge coordinates, 2 decimals
// as CVAT writes them.
std::string BoxCorners(const Box2d& box);

}  // namespace lsds::convert::cvat
