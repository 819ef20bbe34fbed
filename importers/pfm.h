// Portable float maps (PFM), greyscale ("Pf") and colour ("PF"). The PFM
// specification stores rows bottom first; AirSim's writer
// (AirLib common_utils/Utils.hpp writePFMfile) writes them top first, so the
// row order is the caller's to state.
#pragma once

#include <filesystem>
#include <vector>

namespace lsds::import {

struct PfmImage {
  int width = 0, height = 0, channels = 1;
  std::vector<float> values;  // row-major, top row first, channels interleaved
};

enum class PfmRows { kBottomFirst, kTopFirst };

// Throws lsds::Error naming the file (and the header's line:column) for a
// malformed header or a size beyond 32768 x 32768, and, before anything is
// allocated, for data shorter than the header declares or an image beyond the
// memory budget.
PfmImage ReadPfm(const std::filesystem::path& path, PfmRows rows);
// Greyscale, little-endian, atomically.
void WritePfm(const std::filesystem::path& path, const PfmImage& image, PfmRows rows);

}  // namespace lsds::import
