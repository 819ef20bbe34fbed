// NumPy's .npy format (version 1.0), written without Python: the form
// `numpy.load` reads with the exact dtype and shape.
// Spec: https://numpy.org/doc/stable/reference/generated/numpy.lib.format.html
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace lsds::layer_export {

// The 10-byte preamble and the header dictionary, padded with spaces and a
// newline so that the data starts at a multiple of 64 bytes. `descr` is a
// little-endian NumPy type string ("<f4", "<u4", "<u2"); `shape` is C order.
std::string NpyHeader(const std::string& descr,
                      const std::vector<int64_t>& shape);

// Writes header + `bytes` bytes of little-endian data to `path` (not atomic:
// callers write inside an AtomicDirectory). Throws lsds::Error naming the file
// when it cannot be written.
void WriteNpy(const std::filesystem::path& path,
              const std::string& descr,
              const std::vector<int64_t>& shape,
              const void* data,
              size_t bytes);

}  // namespace lsds::layer_export
