// Small helpers the format plug-ins share.
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

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

inline std::ofstream OpenForWrite(const std::filesystem::path& path) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error("cannot write", Location(path.string()));
  return out;
}

// Appends the whole of `path` to `out` and removes it.
inline void AppendAndRemove(std::ofstream& out,
                            const std::filesystem::path& path) {
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
