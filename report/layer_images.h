// Every layer of a frame as a picture people can read: ids in a stable colour
// per id, depth through a colour map with its range, normals as RGB, shadow as
// grey, motion on a flow colour wheel with invalid pixels marked
// (docs/report.md, "Layers").
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "libs/exr/flat_image.h"

namespace lsds::report {

// Ids (channel "id") through IdColor.
cv::Mat ColorizeIds(const exr::FlatImage& ids);

// Depth (channel "Z") through the turbo colour map from its smallest (blue) to
// its largest finite value (red); pixels without a finite depth (sky) are dark
// grey. Writes the range used.
cv::Mat ColorizeDepth(const exr::FlatImage& depth, double* min, double* max);
// The colour map of ColorizeDepth from min (left) to max (right).
cv::Mat DepthScaleBar(int width, int height);

// World-frame unit normals (X, Y, Z) as RGB = (n + 1) / 2; zero normals black.
cv::Mat ColorizeNormals(const exr::FlatImage& normals);

// Shadow ratio (channel Y) as grey: black full shadow, white none.
cv::Mat ColorizeShadow(const exr::FlatImage& shadow);

// Screen-normalized motion (X, Y) converted to pixels: hue = direction, white
// = no motion, full saturation = the largest motion of the frame (written to
// `max_px`). Pixels without valid motion (NaN) are a grey checkerboard;
// `invalid` counts them.
cv::Mat ColorizeMotion(const exr::FlatImage& motion, double* max_px, int64_t* invalid);
// The colour wheel of ColorizeMotion: direction around, magnitude outwards.
cv::Mat FlowWheel(int size);

}  // namespace lsds::report
