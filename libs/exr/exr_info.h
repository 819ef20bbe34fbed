// Reading an EXR header without decoding pixels.
#pragma once

#include <filesystem>

#include "libs/exr/exr_types.h"

namespace lsds::exr {

// Opens the header of a flat or deep scanline EXR and checks `limits`; throws
// lsds::Error naming the file for unreadable files, tiled or multi-part files,
// or files beyond the limits.
ExrInfo ReadExrInfo(const std::filesystem::path& path, const ReadLimits& limits = {});

// The checks every reader here makes before OpenEXR opens a file, for readers
// that open other renderers' EXRs themselves (lsds import): a regular file,
// and a header whose attributes fit in the file and whose data window is
// within `limits` (OpenEXR allocates by the header before anything can look
// at it; libs/exr/header_scan.cc). Throws lsds::Error naming the file.
void CheckExrHeader(const std::filesystem::path& path, const ReadLimits& limits = {});

}  // namespace lsds::exr
