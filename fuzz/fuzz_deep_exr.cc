// libFuzzer target: any byte string read as a deep layer by ReadDeepExr (the
// bundle layers of validate, bundles, report) is decoded or refused with
// lsds::Error; never a crash, leak, hang or allocation beyond ReadLimits.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_input.h"
#include "libs/exr/deep_image.h"
#include "libs/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = lsds::fuzz::ScratchDir() / "bundle.exr";
  lsds::fuzz::WriteBytes(path, data, size);
  try {
    const lsds::exr::DeepImage image = lsds::exr::ReadDeepExr(path, {}, lsds::fuzz::FuzzLimits());
    (void)image.width();
  } catch (const lsds::Error&) {
  }
  return 0;
}
