// OpenEXR's process-wide encoder settings, set once by a command that writes
// many EXR files (lsds generate, lsds import).
#pragma once

namespace lsds::exr {

// The zlib level of the ZIP and ZIPS layers (0-9; 1 encodes about twice as
// fast as OpenEXR's default 4 for files a few percent larger, still lossless)
// and the size of OpenEXR's thread pool, which compresses the chunks of one
// file in parallel (0: one thread per core). Chunks are written in order: the
// bytes do not depend on the thread count.
void SetEncoderSettings(int zip_level, int threads);

}  // namespace lsds::exr
