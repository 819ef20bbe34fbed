#include "libs/importers/pfm.h"

#include <cstring>
#include <fstream>
#include <sstream>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"

namespace lsds::import {

namespace {
bool HostIsLittleEndian() {
  const uint16_t one = 1;
  uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}
}  // namespace

PfmImage ReadPfm(const std::filesystem::path& path, PfmRows rows) {
  const std::string file = path.string();
  RequireRegularFile(path, "PFM file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open", Location(file));
  std::string magic;
  PfmImage image;
  double scale = 0;
  in >> magic >> image.width >> image.height >> scale;
  if (!in || (magic != "Pf" && magic != "PF") || image.width < 1 || image.height < 1 ||
      image.width > 32768 || image.height > 32768 || scale == 0)
    throw Error("not a PFM file (header 'Pf|PF W H SCALE' expected)", Location(file));
  in.get();  // the single whitespace after the scale
  image.channels = magic == "PF" ? 3 : 1;
  const size_t count = static_cast<size_t>(image.width) * image.height * image.channels;
  std::vector<float> raw(count);
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(count * sizeof(float)));
  if (in.gcount() != static_cast<std::streamsize>(count * sizeof(float)))
    throw Error("PFM data is shorter than its header says", Location(file));
  // Negative scale: little-endian data.
  if ((scale < 0) != HostIsLittleEndian()) {
    for (float& v : raw) {
      uint32_t bits;
      std::memcpy(&bits, &v, 4);
      bits = __builtin_bswap32(bits);
      std::memcpy(&v, &bits, 4);
    }
  }
  const size_t row = static_cast<size_t>(image.width) * image.channels;
  image.values.resize(count);
  for (int j = 0; j < image.height; ++j) {
    const int source_row = rows == PfmRows::kTopFirst ? j : image.height - 1 - j;
    std::memcpy(&image.values[j * row], &raw[source_row * row], row * sizeof(float));
  }
  return image;
}

void WritePfm(const std::filesystem::path& path, const PfmImage& image, PfmRows rows) {
  AtomicFile out(path);
  out.stream() << "Pf\n"
               << image.width << " " << image.height << "\n"
               << (HostIsLittleEndian() ? "-1" : "1") << "\n";
  const size_t row = static_cast<size_t>(image.width);
  for (int j = 0; j < image.height; ++j) {
    const int source_row = rows == PfmRows::kTopFirst ? j : image.height - 1 - j;
    out.stream().write(reinterpret_cast<const char*>(&image.values[source_row * row]),
                       static_cast<std::streamsize>(row * sizeof(float)));
  }
  out.Commit();
}

}  // namespace lsds::import
