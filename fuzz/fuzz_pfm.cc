// libFuzzer target: any byte string read as a PFM depth map by ReadPfm (lsds
// import airsim) is read or refused with lsds::Error; never a crash, and no
// allocation before the header is checked against the file and the budget.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_input.h"
#include "importers/pfm.h"
#include "libs/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lsds::fuzz::SmallBudget();
  const std::filesystem::path path = lsds::fuzz::ScratchDir() / "d.pfm";
  lsds::fuzz::WriteBytes(path, data, size);
  for (const auto rows : {lsds::import::PfmRows::kTopFirst, lsds::import::PfmRows::kBottomFirst}) {
    try {
      const lsds::import::PfmImage image = lsds::import::ReadPfm(path, rows);
      (void)image.values.size();
    } catch (const lsds::Error&) {
    }
  }
  return 0;
}
