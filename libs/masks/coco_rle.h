// COCO run-length encoding (pycocotools maskApi): column-major (Fortran order)
// runs over the whole image, alternating background/foreground and starting
// with a background run (0 when the first pixel is foreground); the compressed
// string is rleToString's 6-bit LEB128-like code of the counts, with each count
// after the third stored as the difference to the count two before it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libs/masks/instance_masks.h"

namespace lsds::masks {

// Runs of the full `image_height` x `image_width` image holding `mask` at its
// place.
std::vector<uint32_t> CocoRleCounts(const BoxMask& mask);

// rleToString of the COCO API, bit for bit.
std::string CocoRleToString(const std::vector<uint32_t>& counts);

}  // namespace lsds::masks
