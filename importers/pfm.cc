#include "importers/pfm.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <utility>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/limits.h"
#include "libs/util/text_check.h"

namespace lsds::import {

namespace {
bool HostIsLittleEndian() {
  const uint16_t one = 1;
  uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// The PFM header, "PF|Pf W H SCALE" separated by whitespace, parsed from its
// first bytes with every number range-checked: a stream's `>>` would read a
// token of any length and wrap a huge number.
class PfmHeader {
 public:
  PfmHeader(std::string text, std::string file) : text_(std::move(text)), file_(std::move(file)) {}

  std::string Token(const char* what) {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
    const size_t start = at_;
    while (at_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
    if (at_ == start || at_ == text_.size()) {
      Fail(start,
           std::string("expected the ") + what +
               " (header 'Pf|PF WIDTH HEIGHT SCALE' and one whitespace)");
    }
    token_start_ = start;
    return text_.substr(start, at_ - start);
  }
  int Size(const char* what) {
    const std::string token = Token(what);
    int value = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size() || value < 1 || value > kMaxSide) {
      Fail(token_start_,
           std::string("the ") + what + " '" + Excerpt(token, 40) +
               "' is not a whole number in [1, " + std::to_string(kMaxSide) + "]");
    }
    return value;
  }
  double Scale() {
    const std::string token = Token("scale");
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size() || !std::isfinite(value) || value == 0)
      Fail(token_start_, "the scale '" + Excerpt(token, 40) + "' is not a finite, non-zero number");
    return value;
  }
  // The offset of the data: after the single whitespace that ends the header.
  size_t DataStart() const { return at_ + 1; }
  [[noreturn]] void Fail(size_t offset, const std::string& what) const {
    int line = 0, column = 0;
    LineColumnFromOffset(text_, offset, &line, &column);
    throw Error("not a PFM file: " + what, Location::Text(file_, line, column));
  }

  static constexpr int kMaxSide = 32768;  // exr::ReadLimits' side, for the layer it becomes

 private:
  std::string text_;
  std::string file_;
  size_t at_ = 0;
  size_t token_start_ = 0;
};

}  // namespace

PfmImage ReadPfm(const std::filesystem::path& path, PfmRows rows) {
  const std::string file = path.string();
  RequireRegularFile(path, "PFM file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open", Location(file));
  std::error_code ec;
  const uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec) throw Error("cannot read: " + ec.message(), Location(file));
  // A header is a few dozen bytes; 256 hold any valid one.
  std::string head(256, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  PfmHeader header(std::move(head), file);
  const std::string magic = header.Token("magic 'Pf' or 'PF'");
  if (magic != "Pf" && magic != "PF") header.Fail(0, "the magic is not 'Pf' or 'PF'");
  PfmImage image;
  image.width = header.Size("width");
  image.height = header.Size("height");
  const double scale = header.Scale();
  image.channels = magic == "PF" ? 3 : 1;
  const size_t count = static_cast<size_t>(image.width) * image.height * image.channels;
  const uint64_t need = count * sizeof(float);
  const uint64_t have = file_size - std::min<uint64_t>(file_size, header.DataStart());
  // Checked against the file before anything is allocated: an 18-byte header
  // may declare 32768 x 32768 x 3 floats (12 GiB).
  if (have < need) {
    throw Error("PFM data is shorter than its header says: " + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + "x" + std::to_string(image.channels) +
                    " floats need " + std::to_string(need) + " bytes, the file has " +
                    std::to_string(have) + " after its header",
                Location(file));
  }
  CheckImageBudget(image.width, image.height, image.channels, sizeof(float), "PFM image", file);
  image.values.resize(count);
  in.clear();
  in.seekg(static_cast<std::streamoff>(header.DataStart()));
  in.read(reinterpret_cast<char*>(image.values.data()), static_cast<std::streamsize>(need));
  if (static_cast<uint64_t>(in.gcount()) != need)
    throw Error("PFM data is shorter than its header says", Location(file));
  // Negative scale: little-endian data.
  if ((scale < 0) != HostIsLittleEndian()) {
    for (float& v : image.values) {
      uint32_t bits;
      std::memcpy(&bits, &v, 4);
      bits = __builtin_bswap32(bits);
      std::memcpy(&v, &bits, 4);
    }
  }
  // Rows in place: the file's bottom row first becomes row 0 last.
  if (rows == PfmRows::kBottomFirst) {
    const size_t row = static_cast<size_t>(image.width) * image.channels;
    for (int j = 0; j < image.height / 2; ++j) {
      std::swap_ranges(image.values.begin() + static_cast<ptrdiff_t>(j * row),
                       image.values.begin() + static_cast<ptrdiff_t>((j + 1) * row),
                       image.values.begin() + static_cast<ptrdiff_t>((image.height - 1 - j) * row));
    }
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
