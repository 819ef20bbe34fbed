#include "importers/indexed_png.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "importers/source_png.h"
#include "libs/util/error.h"

namespace lsds::import {

namespace fs = std::filesystem;

namespace {
struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

void OnPngError(png_structp png, png_const_charp message) {
  *static_cast<std::string*>(png_get_error_ptr(png)) = message;
  std::longjmp(png_jmpbuf(png), 1);
}
void OnPngWarning(png_structp, png_const_charp) {}

// libpng reports errors by longjmp to the setjmp in Guarded(): that function
// holds no object with a destructor and changes no local after setjmp, and the
// work runs in functions that are never inlined into it (a longjmp out of
// them skips no destructor of theirs: they only fill the caller's objects).
template <typename Work>
bool Guarded(png_structp png, const Work& work) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  work();
  return true;
}

// Reads the image into `image` through `rows`; `wrong_kind` when it is not
// 8-bit (or less) palette or greyscale.
[[gnu::noinline]] void ReadPixels(png_structp png,
                                  png_infop info,
                                  std::FILE* file,
                                  IndexImage* image,
                                  std::vector<png_bytep>* rows,
                                  bool* wrong_kind) {
  png_init_io(png, file);
  png_read_info(png, info);
  const int colour = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  if ((colour != PNG_COLOR_TYPE_PALETTE && colour != PNG_COLOR_TYPE_GRAY) || depth > 8) {
    *wrong_kind = true;
    return;
  }
  if (depth < 8) png_set_packing(png);
  png_read_update_info(png, info);
  image->width = static_cast<int>(png_get_image_width(png, info));
  image->height = static_cast<int>(png_get_image_height(png, info));
  image->index.resize(static_cast<size_t>(image->width) * image->height);
  rows->resize(static_cast<size_t>(image->height));
  for (int j = 0; j < image->height; ++j)
    (*rows)[j] = image->index.data() + static_cast<size_t>(j) * image->width;
  png_read_image(png, rows->data());
  png_read_end(png, nullptr);
}

[[gnu::noinline]] void WritePixels(png_structp png,
                                   png_infop info,
                                   std::FILE* file,
                                   const IndexImage& image,
                                   std::vector<png_color>* palette,
                                   std::vector<png_bytep>* rows) {
  png_init_io(png, file);
  png_set_IHDR(png,
               info,
               image.width,
               image.height,
               8,
               PNG_COLOR_TYPE_PALETTE,
               PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_PLTE(png, info, palette->data(), static_cast<int>(palette->size()));
  png_write_info(png, info);
  png_write_image(png, rows->data());
  png_write_end(png, nullptr);
}

}  // namespace

IndexImage ReadIndexedPng(const fs::path& path) {
  // The header first: libpng would size the image by it (a 100-byte file
  // can declare 40000 x 40000) before its data turns out to be missing.
  const std::optional<PngHeader> header = ReadPngHeader(path);
  if (!header) throw Error("not a PNG file (no PNG signature)", Location(path.string()));
  CheckPngSize(path, *header, 1);
  File file(std::fopen(path.string().c_str(), "rb"));
  if (!file) throw Error("cannot open", Location(path.string()));
  std::string message;
  png_structp png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, &message, OnPngError, OnPngWarning);
  png_infop info = png_create_info_struct(png);
  IndexImage image;
  std::vector<png_bytep> rows;
  bool wrong_kind = false;
  const bool read =
      Guarded(png, [&] { ReadPixels(png, info, file.get(), &image, &rows, &wrong_kind); });
  png_destroy_read_struct(&png, &info, nullptr);
  if (!read) throw Error("not a readable PNG: " + message, Location(path.string()));
  if (wrong_kind)
    throw Error("expected an 8-bit indexed (palette) or greyscale PNG", Location(path.string()));
  return image;
}

void WriteIndexedPng(const fs::path& path,
                     const IndexImage& image,
                     const std::vector<uint8_t>& palette_rgb) {
  File file(std::fopen(path.string().c_str(), "wb"));
  if (!file) throw Error("cannot create", Location(path.string()));
  std::string message;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &message, OnPngError, OnPngWarning);
  png_infop info = png_create_info_struct(png);
  std::vector<png_color> palette(palette_rgb.size() / 3);
  for (size_t k = 0; k < palette.size(); ++k)
    palette[k] = {palette_rgb[3 * k], palette_rgb[3 * k + 1], palette_rgb[3 * k + 2]};
  std::vector<png_bytep> rows(static_cast<size_t>(image.height));
  for (int j = 0; j < image.height; ++j)
    rows[j] = const_cast<png_bytep>(image.index.data() + static_cast<size_t>(j) * image.width);
  const bool written =
      Guarded(png, [&] { WritePixels(png, info, file.get(), image, &palette, &rows); });
  png_destroy_write_struct(&png, &info);
  if (!written) throw Error("cannot write PNG: " + message, Location(path.string()));
}

}  // namespace lsds::import
