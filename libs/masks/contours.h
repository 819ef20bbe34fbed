// Polygons of an instance mask, traced along pixel edges.
//
// Conventions (docs/convert.md): vertices lie on pixel corners (integer
// pixel-edge coordinates) and the polygon follows the outer boundary of the
// piece's pixels, so that pycocotools' rasterizer (maskApi.c rleFrPoly, which
// samples pixel centres) gives back exactly the piece's pixels, and the
// polygon's min/max (Ultralytics' segment2box) is the pixel-edge box. Pieces
// are 8-connected; where two pixels touch only at a corner the polygon passes
// that corner twice. Polygons cannot hold holes: holes are filled (and
// counted).
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "libs/masks/instance_masks.h"

namespace lsds::masks {

using Polygon = std::vector<cv::Point2d>;  // image pixel-edge coordinates

struct MaskPolygons {
  std::vector<Polygon> pieces;  // one outer boundary per connected piece
                                // (8-connected), largest first
  int holes = 0;                // holes that the polygons fill
  int64_t hole_pixels = 0;      // pixels of those holes: the filled polygons
                                // cover pixel_count + hole_pixels pixels
};

// Where the vertices lie.
enum class PolygonVertices {
  // On pixel corners: exact for rasterizers that sample pixel centres
  // (pycocotools, CVAT).
  kPixelCorners,
  // Each corner moved kCornerInset pixels into the piece's pixel at that
  // corner (at a concave corner, the pixel diagonal to the missing one), for
  // rasterizers that truncate vertices to pixel indices and fill the polygon
  // with its boundary (Ultralytics' polygon2mask: an int32 cast, then
  // cv2.fillPoly): truncation then gives the boundary pixels, whose polygon
  // fills exactly the piece, while the polygon and its min/max stay within
  // kCornerInset of the pixel-edge ones.
  kInsetCorners,
};
// Larger than the rounding of 6-decimal normalized coordinates and of
// float32 (Ultralytics reads labels as float32) on images up to 25,000 pixels.
inline constexpr double kCornerInset = 1.0 / 64;

MaskPolygons ExtractPolygons(const BoxMask& mask,
                             PolygonVertices vertices = PolygonVertices::kPixelCorners);

// One polygon for an instance in several pieces: the pieces joined by
// zero-width bridges (there and back along the shortest segment between a
// vertex of the polygon so far and a vertex of the next piece), as Ultralytics'
// own converters do. Filled, it covers every piece.
Polygon MergePieces(const std::vector<Polygon>& pieces);

}  // namespace lsds::masks
