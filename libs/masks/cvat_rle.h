// CVAT for images 1.1 mask RLE: runs over the tight box only (`left top width
// height`), row-major, alternating background/foreground and starting with a
// background run (0 when the box's first pixel is foreground). Written as CVAT
// writes it: "a, b, c".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libs/masks/instance_masks.h"

namespace lsds::masks {

std::vector<uint32_t> CvatRleCounts(const BoxMask& mask);
std::string CvatRleToString(const std::vector<uint32_t>& counts);

}  // namespace lsds::masks
