// A picture of where the mixed pixels of a frame lie (docs/images/, `lsds
// bundles --mixed-map`).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "bundles/bundle_stats.h"

namespace lsds::bundle {

// PNG (OpenCV): pure pixels in a dim colour per majority instance (black for
// background), mixed pixels from yellow (purity near 1) to red (purity 0.5) to
// magenta (lower), flying-free.
// The picture of WriteMixedMapPng as interleaved 8-bit BGR rows (OpenCV's
// order), for callers that encode it themselves (`lsds report`).
std::vector<uint8_t> MixedMapBgr(const PixelMaps& maps, int width, int height);

void WriteMixedMapPng(const std::filesystem::path& path,
                      const PixelMaps& maps,
                      int width,
                      int height);

}  // namespace lsds::bundle
