// libFuzzer target: any byte string read as a flat layer by ReadFlatExr (every
// command reads flat layers through it) is decoded or refused with
// lsds::Error; never a crash, leak, hang or allocation beyond ReadLimits.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_input.h"
#include "libs/exr/flat_image.h"
#include "libs/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = lsds::fuzz::ScratchDir() / "layer.exr";
  lsds::fuzz::WriteBytes(path, data, size);
  // Limits small enough that a hostile header cannot make one run slow, as
  // the readers' own limits bound a real run.
  lsds::exr::ReadLimits limits;
  limits.max_width = limits.max_height = 4096;
  limits.max_pixels = 1 << 20;
  try {
    const lsds::exr::FlatImage image = lsds::exr::ReadFlatExr(path, {}, limits);
    (void)image.width();
  } catch (const lsds::Error&) {
  }
  return 0;
}
