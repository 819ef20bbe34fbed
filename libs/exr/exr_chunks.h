// Whether an EXR holds all of its pixel data. A file cut short (an interrupted
// copy, a full disk) keeps a readable header: only its chunk table and the
// chunks' leaders tell, and reading them costs a few bytes per chunk, not the
// decoding of the pixels.
#pragma once

#include <cstdint>
#include <filesystem>

namespace lsds::exr {

// Throws lsds::Error naming `path` unless every chunk of the single-part
// scanline EXR (flat or deep) lies within the file's `file_size` bytes: a
// chunk table entry outside the file, or a chunk whose data (and, deep, sample
// count table) ends past the end, means the file was truncated. Read the
// header with ReadExrInfo first: it applies the reader's limits.
void CheckChunksWithinFile(const std::filesystem::path& path, uint64_t file_size);

}  // namespace lsds::exr
