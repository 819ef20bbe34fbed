// Helpers shared by the EXR readers and writers; not part of the public
// interface.
#pragma once

#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfPixelType.h>

#include <exception>
#include <filesystem>
#include <string>

#include "libs/exr/exr_types.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"

namespace lsds::exr::internal {

Imf::PixelType ToImf(PixelType type);
Imf::Compression ToImf(Compression compression);
void AddCamera(const WriteOptions& options, Imf::Header* header);
void AddAttributes(const WriteOptions& options, Imf::Header* header);
ExrInfo InfoFromHeader(const Imf::Header& header);
void CheckLimits(const std::filesystem::path& path,
                 const Imf::Header& header,
                 const ReadLimits& limits);

// Refuses, before OpenEXR reads the file, a header whose attributes declare
// more bytes than the file has or whose data window is beyond `limits`:
// OpenEXR allocates by the header first (libs/exr/header_scan.cc).
void ScanHeader(const std::filesystem::path& path, const ReadLimits& limits);

// Runs `body`, turning OpenEXR's exceptions into lsds::Error that names the
// file.
template <typename Body>
auto GuardExr(const std::filesystem::path& path, Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const lsds::Error&) {
    throw;
  } catch (const std::exception& e) {
    throw lsds::Error(std::string("cannot read or write EXR: ") + e.what(),
                      Location(path.string()));
  }
}

// OpenEXR's output stream over lsds's one atomic-output path: every write is
// checked, the file is synced and renamed into place by AtomicFile::Commit().
class AtomicOStream : public Imf::OStream {
 public:
  explicit AtomicOStream(AtomicFile& file) : Imf::OStream(file.path().c_str()), file_(file) {}
  void write(const char c[], int n) override {
    file_.stream().write(c, n);
    if (!file_.stream()) file_.Check();  // throws naming the file and errno
  }
  uint64_t tellp() override { return static_cast<uint64_t>(file_.stream().tellp()); }
  void seekp(uint64_t pos) override {
    file_.stream().seekp(static_cast<std::streamoff>(pos));
    if (!file_.stream()) file_.Check();
  }

 private:
  AtomicFile& file_;
};

// Runs `write` with an OStream for `path`, then commits it; on failure
// nothing appears under `path`.
template <typename Write>
void WriteAtomicExr(const std::filesystem::path& path, Write&& write) {
  GuardExr(path, [&] {
    AtomicFile file(path);
    {
      AtomicOStream stream(file);
      write(stream);
    }
    file.Commit();
    return 0;
  });
}

}  // namespace lsds::exr::internal
