// libFuzzer target: any byte string read as the PNGs of lsds import: through
// OpenCV (ReadImage, every colour, depth and mask PNG, and ReadSrgbLayer at the
// size its header declares) and through libpng (ReadIndexedPng, Kubric's
// palette segmentation) is read or refused with lsds::Error; never a crash,
// an escaped cv::Exception, or a decode beyond the limits and the budget.
#include <cstddef>
#include <cstdint>
#include <optional>

#include <opencv2/imgcodecs.hpp>

#include "fuzz/fuzz_input.h"
#include "importers/indexed_png.h"
#include "importers/source_png.h"
#include "libs/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lsds::fuzz::SmallBudget();
  const std::filesystem::path path = lsds::fuzz::ScratchDir() / "a.png";
  lsds::fuzz::WriteBytes(path, data, size);
  namespace import = lsds::import;
  try {
    (void)import::ReadIndexedPng(path).index.size();
  } catch (const lsds::Error&) {
  }
  for (const int flags : {cv::IMREAD_UNCHANGED, cv::IMREAD_COLOR, cv::IMREAD_GRAYSCALE}) {
    try {
      (void)import::ReadImage(path, flags).total();
    } catch (const lsds::Error&) {
    }
  }
  try {
    if (const std::optional<import::PngHeader> header = import::ReadPngHeader(path)) {
      (void)import::ReadSrgbLayer(
          path, static_cast<int>(header->width), static_cast<int>(header->height), "fuzz");
    }
  } catch (const lsds::Error&) {
  }
  return 0;
}
