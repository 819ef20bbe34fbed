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
  try {
    const lsds::exr::FlatImage image = lsds::exr::ReadFlatExr(path, {}, lsds::fuzz::FuzzLimits());
    (void)image.width();
  } catch (const lsds::Error&) {
  }
  return 0;
}
