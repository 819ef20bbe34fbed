// libFuzzer target: any byte string read as a .npy file by ReadNpy (lsds
// import replicator: bounding boxes, distance to camera) is read or refused
// with lsds::Error; never a crash, a stack overflow on a nested header, a
// quadratic header, or an allocation beyond the file or the budget.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_input.h"
#include "libs/util/error.h"
#include "libs/util/npy.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lsds::fuzz::SmallBudget();
  const std::filesystem::path path = lsds::fuzz::ScratchDir() / "a.npy";
  lsds::fuzz::WriteBytes(path, data, size);
  try {
    const lsds::NpyArray array = lsds::ReadNpy(path);
    // Every value of the first and the last record, as the importer reads them.
    const int64_t n = array.size();
    if (n > 0) {
      for (const lsds::NpyField& field : array.fields) {
        for (int64_t k = 0; k < field.count && k < 64; ++k) {
          (void)array.Get(0, field, k);
          (void)array.Get(n - 1, field, k);
        }
      }
    }
  } catch (const lsds::Error&) {
  }
  return 0;
}
