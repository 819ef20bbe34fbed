// The film of one frame: named flat layers (the standard layers of
// docs/format.md), the deep pixel bundle, and what the truth needs (the centre
// sample's position per pixel, ray counts).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "libs/exr/deep_image.h"
#include "libs/exr/flat_image.h"

namespace lsds::gen {

struct Film {
  std::map<std::string, exr::FlatImage> flat;  // by layer semantic
  exr::DeepImage bundle;
  std::vector<Eigen::Vector2f> centre_sample;  // per pixel, the position of bundle sample 0
  uint64_t rays = 0;                           // primary + shadow rays cast

  // The film for `semantics` (flat channels from StandardLayer) at the given
  // size and samples.
  // Without `with_bundle` the bundle stays empty (0 x 0).
  static Film Make(int width, int height, int spp, bool with_bundle = true);

  // Makes `film` such a film. When it already has this shape its buffers are
  // kept, values included: for RenderFrame, which writes every value, a
  // reused film costs no allocation and no page faults.
  static void Reshape(int width, int height, int spp, bool with_bundle, Film* film);

  // The bytes one pixel of such a film takes: checked against the memory
  // budget (libs/util/limits.h) before a frame is rendered.
  static uint64_t BytesPerPixel(int spp, bool with_bundle = true);
};

}  // namespace lsds::gen
