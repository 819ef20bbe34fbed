// Inputs are read only from regular files: a FIFO, a device or a socket given
// as a scene, layer or JSON file would block or never end (docs/reliability.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "libs/util/error.h"

namespace lsds {

// Throws lsds::Error naming `path` unless it is a regular file (symlinks
// followed). `what` says which input it is ("scene file", "layer file").
void RequireRegularFile(const std::filesystem::path& path, const std::string& what = "input");

// Reads a whole file into one buffer sized as it is read (no stream buffer
// and no second copy), after checking its size against the memory budget
// (libs/util/limits.h); with `text`, a NUL byte is an error at its
// line:column, found chunk by chunk as the file is read, so a binary or
// sparse file is refused after its first megabyte, not after all of it.
// ReadFile (atomic_file.h) is ReadWholeFile(path, false).
std::string ReadWholeFile(const std::filesystem::path& path, bool text);
// For text inputs (JSON, LSCENE/LCAP).
std::string ReadTextFile(const std::filesystem::path& path);

// `path` at the line and column of its byte `offset`, for an error a
// streaming reader finds where it keeps no text: the file is read again up to
// the offset, on the error path only.
Location TextLocationInFile(const std::filesystem::path& path, uint64_t offset);

}  // namespace lsds
