// Inputs are read only from regular files: a FIFO, a device or a socket given
// as a scene, layer or JSON file would block or never end (docs/reliability.md).
#pragma once

#include <filesystem>
#include <string>

namespace lsds {

// Throws lsds::Error naming `path` unless it is a regular file (symlinks
// followed). `what` says which input it is ("scene file", "layer file").
void RequireRegularFile(const std::filesystem::path& path, const std::string& what = "input");

}  // namespace lsds
