// COCO run-length encoding (pycocotools maskApi): column-major (Fortran order)
// runs over the whole image, alternating background/foreground and starting
// with a background run (0 when the first pixel is foreground); the compressed
// string is rleToString's 6-bit LEB128-like code of the counts, with each count
// after the third stored as the difference to the count two before it.
// The reading side (decoding, areas, IoU, polygons) follows maskApi.c of
// cocodataset/cocoapi at 8c9bcc3, each function named beside its port.
#pragma once

#include <array>
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

namespace lsds::masks {

// A COCO RLE of a `height` x `width` image (maskApi.h's RLE).
struct CocoRle {
  int64_t height = 0, width = 0;
  std::vector<uint32_t> counts;
};

// rleFrString: the counts of a compressed string. Returns false (and leaves
// `counts` undefined) for a character outside '0'..'o', a string that ends in
// the middle of a count, or a count below 0 or above 2^32 - 1, where the COCO
// API would read memory or numbers it never wrote.
bool CocoRleFromString(const std::string& text, std::vector<uint32_t>* counts);

// rleArea: the foreground pixels (every second run).
uint64_t CocoRleArea(const std::vector<uint32_t>& counts);

// rleToBbox: the tight [x, y, width, height] of the foreground (all 0 for
// none), in pixels.
std::array<double, 4> CocoRleBox(const CocoRle& rle);

// rleIou for one pair of the same size: intersection over union, or over the
// detection's area when `crowd` (maskApi.c:77-96); 0 when they do not meet.
double CocoRleIou(const CocoRle& detection, const CocoRle& ground_truth, bool crowd);

// The largest |coordinate| CocoRleFromPolygon takes. rleFrPoly walks every
// edge in steps of 1/5 pixel in int: past this the walk takes minutes and at
// 4.3e8 the int overflows (the COCO API's own behaviour there is undefined).
// A vertex of a real mask is within the image or near it.
inline constexpr double kMaxPolygonCoordinate = 1e6;

// rleFrPoly: the mask of one polygon [x0, y0, x1, y1, ...] (pixel-edge
// coordinates, each within +-kMaxPolygonCoordinate), rasterised bit for bit
// as the COCO API does.
CocoRle CocoRleFromPolygon(const std::vector<double>& xy, int64_t height, int64_t width);

// rleMerge with intersect = 0: the union of masks of one size (an empty
// image's RLE for none).
CocoRle CocoRleUnion(const std::vector<CocoRle>& masks);

}  // namespace lsds::masks
