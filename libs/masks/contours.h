// Polygons of an instance mask, from OpenCV contours (cv::findContours,
// CHAIN_APPROX_SIMPLE: only collinear points are dropped, nothing else is
// simplified).
//
// Conventions (docs/convert.md): vertices are the centres of the mask's
// boundary pixels in pixel-edge coordinates, (x + 0.5, y + 0.5), so every
// polygon lies inside the object's pixel-edge box. A piece whose contour has
// fewer than 3 distinct points (a single pixel, a 1-pixel-wide line) is written
// as the pixel-edge rectangle of its pixels. Polygons cannot hold holes: holes
// are filled (and counted).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "libs/masks/instance_masks.h"

namespace lsds::masks {

using Polygon = std::vector<cv::Point2d>;  // image pixel-edge coordinates

struct MaskPolygons {
  std::vector<Polygon> pieces;  // one outer boundary per connected piece
                                // (8-connected), largest first
  int holes = 0;                // holes that the polygons fill
};

MaskPolygons ExtractPolygons(const BoxMask& mask);

// One polygon for an instance in several pieces: the pieces joined by
// zero-width bridges (there and back along the shortest segment between a
// vertex of the polygon so far and a vertex of the next piece), as Ultralytics'
// own converters do. Filled, it covers every piece.
Polygon MergePieces(const std::vector<Polygon>& pieces);

}  // namespace lsds::masks
