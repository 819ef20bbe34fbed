// Small helpers the format plug-ins share.
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"

namespace lsds::convert {

// printf-style formatting into a std::string (numbers in files are written with
// explicit precision, independent of the locale of iostreams).
template <typename... Args>
std::string Format(const char* format, Args... args) {
  char buffer[128];
  const int n = std::snprintf(buffer, sizeof(buffer), format, args...);
  if (n < static_cast<int>(sizeof(buffer))) return std::string(buffer, n);
  std::string out(n + 1, '\0');
  std::snprintf(out.data(), out.size(), format, args...);
  out.resize(n);
  return out;
}

// A converter's files go through the one checked, atomic output path: the
// content appears under `path` at Commit().
inline std::unique_ptr<AtomicFile> OpenForWrite(const std::filesystem::path& path) {
  std::filesystem::create_directories(path.parent_path());
  return std::make_unique<AtomicFile>(path);
}

// Appends the whole of `path` to `out` and removes it.
inline void AppendAndRemove(std::ostream& out, const std::filesystem::path& path) {
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot read back", Location(path.string()));
    // operator<< of an empty streambuf sets failbit on `out`: copy only when
    // there is something.
    if (in.peek() != std::ifstream::traits_type::eof()) out << in.rdbuf();
  }
  std::filesystem::remove(path);
}

}  // namespace lsds::convert
