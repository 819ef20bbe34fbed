#include "importers/source_png.h"

#include <array>
#include <cstring>
#include <fstream>

#include "libs/imaging/image_codecs.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/limits.h"
#include "libs/util/srgb.h"
#include "libs/util/strings.h"

namespace lsds::import {

namespace {

uint32_t BigEndian32(const unsigned char* b) {
  return uint32_t{b[0]} << 24 | uint32_t{b[1]} << 16 | uint32_t{b[2]} << 8 | b[3];
}

// Bytes per pixel of the Mat cv::imread makes of `header` with `flags`.
int64_t DecodedBytesPerPixel(const PngHeader& header, int flags) {
  const int64_t value_bytes = header.bit_depth == 16 && (flags & cv::IMREAD_ANYDEPTH) != 0 ? 2 : 1;
  if ((flags & cv::IMREAD_COLOR) == 0 && flags != cv::IMREAD_UNCHANGED) return value_bytes;
  // Unchanged: grey stays 1 channel (2 with alpha); colour and palette 3 or 4.
  if (flags == cv::IMREAD_UNCHANGED) return value_bytes * 4;
  return value_bytes * 3;
}

}  // namespace

int PngHeader::Samples() const {
  switch (colour_type) {
    case 2:
      return 3;
    case 4:
      return 2;
    case 6:
      return 4;
    default:
      return 1;
  }
}

std::optional<PngHeader> ReadPngHeader(const std::filesystem::path& path) {
  const std::string file = path.string();
  RequireRegularFile(path, "image file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open for reading", Location(file));
  unsigned char b[33] = {};
  in.read(reinterpret_cast<char*>(b), sizeof b);
  const auto got = static_cast<size_t>(in.gcount());
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (got < 8 || std::memcmp(b, kSignature, 8) != 0) return std::nullopt;
  if (got < sizeof b || BigEndian32(b + 8) != 13 || std::memcmp(b + 12, "IHDR", 4) != 0)
    throw Error("malformed PNG: no 13-byte IHDR chunk at byte 8", Location(file));
  PngHeader header;
  header.width = BigEndian32(b + 16);
  header.height = BigEndian32(b + 20);
  header.bit_depth = b[24];
  header.colour_type = b[25];
  const bool depth_ok = header.bit_depth == 1 || header.bit_depth == 2 || header.bit_depth == 4 ||
                        header.bit_depth == 8 || header.bit_depth == 16;
  const bool type_ok = header.colour_type == 0 || header.colour_type == 2 ||
                       header.colour_type == 3 || header.colour_type == 4 ||
                       header.colour_type == 6;
  if (!depth_ok || !type_ok) {
    throw Error("malformed PNG: IHDR at byte 8 declares bit depth " +
                    std::to_string(header.bit_depth) + " with colour type " +
                    std::to_string(header.colour_type),
                Location(file));
  }
  return header;
}

void CheckPngSize(const std::filesystem::path& path,
                  const PngHeader& header,
                  int64_t bytes_per_pixel) {
  const std::string file = path.string();
  const exr::ReadLimits limits;
  const std::string size = std::to_string(header.width) + "x" + std::to_string(header.height);
  if (header.width < 1 || header.height < 1 || header.width > limits.max_width ||
      header.height > limits.max_height || header.width * header.height > limits.max_pixels) {
    throw Error("PNG header (IHDR, byte 16) declares " + size +
                    " pixels: empty or beyond the readers' limits (" +
                    std::to_string(limits.max_width) + " a side, " +
                    std::to_string(limits.max_pixels) + " pixels)",
                Location(file));
  }
  // Deflate expands at most 1032:1 (a 258-byte match in two bits), so the
  // file bounds the pixel bytes it can hold; checked in double, no overflow.
  std::error_code ec;
  const double file_bytes = static_cast<double>(std::filesystem::file_size(path, ec));
  const double pixel_bytes = static_cast<double>(header.width) *
                             static_cast<double>(header.height) *
                             (header.Samples() * header.bit_depth) / 8.0;
  if (!ec && pixel_bytes > 1032.0 * file_bytes + 1024) {
    throw Error("PNG header (IHDR, byte 16) declares " + size + " pixels, " +
                    FormatBytes(pixel_bytes) + " of pixel data, more than a file of " +
                    FormatBytes(file_bytes) + " can hold",
                Location(file));
  }
  CheckImageBudget(header.width, header.height, bytes_per_pixel, 1, "decoding the PNG image", file);
}

cv::Mat ReadImage(const std::filesystem::path& path, int flags) {
  // Missing: empty, as from cv::imread, for the caller's message; a FIFO or a
  // folder is refused (OpenCV would block on a FIFO).
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return {};
  if (const std::optional<PngHeader> header = ReadPngHeader(path))
    CheckPngSize(path, *header, DecodedBytesPerPixel(*header, flags));
  try {
    return imaging::ImRead(path.string(), flags);
  } catch (const cv::Exception& e) {
    throw Error("cannot decode the image: " + e.msg, Location(path.string()));
  }
}

exr::FlatImage ReadSrgbLayer(const std::filesystem::path& path,
                             int width,
                             int height,
                             const std::string& size_source) {
  const std::string expected = "a " + std::to_string(width) + "x" + std::to_string(height) +
                               " RGB(A) PNG (" + size_source + ")";
  if (!std::filesystem::is_regular_file(path))
    throw Error("missing or not a file: expected " + expected, Location(path.string()));
  // The size is known: a header that declares another is refused unread.
  if (const std::optional<PngHeader> header = ReadPngHeader(path)) {
    if (header->width != width || header->height != height) {
      throw Error("the PNG header declares " + std::to_string(header->width) + "x" +
                      std::to_string(header->height) + ", expected " + expected,
                  Location(path.string()));
    }
  }
  const cv::Mat image = ReadImage(path, cv::IMREAD_UNCHANGED);
  if (image.empty() || image.cols != width || image.rows != height ||
      (image.depth() != CV_8U && image.depth() != CV_16U) || image.channels() < 3)
    throw Error("missing, unreadable or not a " + std::to_string(width) + "x" +
                    std::to_string(height) + " RGB(A) PNG (" + size_source + ")",
                Location(path.string()));
  const double scale = image.depth() == CV_8U ? 1 / 255.0 : 1 / 65535.0;
  const int channels = image.channels();
  exr::FlatImage rgb(width, height);
  float* channel[3] = {rgb.AddChannel("R", exr::PixelType::kHalf).floats.data(),
                       rgb.AddChannel("G", exr::PixelType::kHalf).floats.data(),
                       rgb.AddChannel("B", exr::PixelType::kHalf).floats.data()};
  // 8-bit values have 256 linear values: looked up, not recomputed per pixel (the same
  // expression, so the same floats).
  static const std::array<float, 256> linear_of_8bit = [] {
    std::array<float, 256> table{};
    for (int v = 0; v < 256; ++v) table[static_cast<size_t>(v)] = LinearFromSrgb(v * (1 / 255.0));
    return table;
  }();
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      for (int c = 0; c < 3; ++c) {
        // OpenCV's order is B, G, R(, A).
        const int k = i * channels + (2 - c);
        channel[c][rgb.Index(i, j)] = image.depth() == CV_8U
                                          ? linear_of_8bit[image.ptr<uint8_t>(j)[k]]
                                          : LinearFromSrgb(image.ptr<uint16_t>(j)[k] * scale);
      }
  return rgb;
}

cv::Mat ReadRgbaPng(const std::filesystem::path& path, int width, int height) {
  if (!std::filesystem::is_regular_file(path))
    throw Error("missing or not a file: expected a " + std::to_string(width) + "x" +
                    std::to_string(height) + " 8-bit RGBA PNG",
                Location(path.string()));
  if (const std::optional<PngHeader> header = ReadPngHeader(path)) {
    if (header->width != width || header->height != height) {
      throw Error("the PNG header declares " + std::to_string(header->width) + "x" +
                      std::to_string(header->height) + ", expected a " + std::to_string(width) +
                      "x" + std::to_string(height) + " 8-bit RGBA PNG",
                  Location(path.string()));
    }
  }
  cv::Mat colours = ReadImage(path, cv::IMREAD_UNCHANGED);
  if (colours.empty() || colours.type() != CV_8UC4 || colours.cols != width ||
      colours.rows != height)
    throw Error("missing, unreadable or not a " + std::to_string(width) + "x" +
                    std::to_string(height) + " 8-bit RGBA PNG",
                Location(path.string()));
  return colours;
}

std::string RgbaText(uint32_t rgba) {
  return "(" + std::to_string(rgba >> 24) + ", " + std::to_string((rgba >> 16) & 0xff) + ", " +
         std::to_string((rgba >> 8) & 0xff) + ", " + std::to_string(rgba & 0xff) + ")";
}

}  // namespace lsds::import
