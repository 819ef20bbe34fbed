// Reading an EXR header without decoding pixels.
#pragma once

#include <filesystem>

#include "libs/exr/exr_types.h"

namespace lsds::exr {

// Opens the header of a flat or deep scanline EXR and checks `limits`; throws
// lsds::Error naming the file for unreadable files, tiled or multi-part files,
// or files beyond the limits.
ExrInfo ReadExrInfo(const std::filesystem::path& path, const ReadLimits& limits = {});

}  // namespace lsds::exr
