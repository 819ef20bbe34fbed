// Helpers shared by the EXR readers and writers; not part of the public
// interface.
#pragma once

#include <ImfHeader.h>
#include <ImfPixelType.h>

#include <exception>
#include <filesystem>
#include <string>

#include "libs/exr/exr_types.h"
#include "libs/util/error.h"

namespace lsds::exr::internal {

Imf::PixelType ToImf(PixelType type);
Imf::Compression ToImf(Compression compression);
void AddCamera(const WriteOptions& options, Imf::Header* header);
ExrInfo InfoFromHeader(const Imf::Header& header);
void CheckLimits(const std::filesystem::path& path,
                 const Imf::Header& header,
                 const ReadLimits& limits);

// Runs `body`, turning OpenEXR's exceptions into lsds::Error that names the
// file.
template <typename Body>
auto GuardExr(const std::filesystem::path& path, Body&& body)
    -> decltype(body()) {
  try {
    return body();
  } catch (const lsds::Error&) {
    throw;
  } catch (const std::exception& e) {
    throw lsds::Error(std::string("cannot read or write EXR: ") + e.what(),
                      Location(path.string()));
  }
}

// Runs `write` (which writes `temp`), then renames `temp` to `path`; on failure
// removes `temp`.
template <typename Write>
void WriteThroughTemp(const std::filesystem::path& path,
                      const std::filesystem::path& temp,
                      Write&& write) {
  try {
    GuardExr(path, [&] {
      write();
      std::filesystem::rename(temp, path);
      return 0;
    });
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw;
  }
}

}  // namespace lsds::exr::internal
