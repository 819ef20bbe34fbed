// libFuzzer target: the validator entry point (ValidateCollection, what
// `lsds validate` runs) over a small real collection whose collection.json is
// the input: the layers stay those of the collection the seed corpus was
// built from (LSDS_FUZZ_LAYERS, copied once), so the frame and cross-layer
// checks run on real pixels. Every input is validated (a report, exit 0 or 1
// in the CLI) or refused with lsds::Error; never a crash, leak or hang.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include "fuzz/fuzz_input.h"
#include "libs/collection/model.h"
#include "libs/util/error.h"
#include "validators/validate.h"

namespace fs = std::filesystem;

namespace {

fs::path Collection() {
  static const fs::path root = [] {
    fs::path dir = lsds::fuzz::ScratchDir() / "C";
    fs::create_directories(dir);
    // The layers of the seed collection, when given (fuzz/README.md).
    // NOLINTNEXTLINE(concurrency-mt-unsafe): lsds never sets the environment
    if (const char* layers = std::getenv("LSDS_FUZZ_LAYERS")) {
      for (const fs::directory_entry& entry : fs::directory_iterator(layers)) {
        if (entry.is_directory()) {
          fs::copy(entry.path(), dir / entry.path().filename(), fs::copy_options::recursive);
        }
      }
    }
    return dir;
  }();
  return root;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path root = Collection();
  lsds::fuzz::WriteBytes(root / lsds::kCollectionFile, data, size);
  lsds::validate::ValidateOptions options;
  options.jobs = 1;
  options.camera_grid = 4;  // the camera solve is fuzzed too, on a coarse grid
  try {
    (void)lsds::validate::ValidateCollection(root, options);
  } catch (const lsds::Error&) {
  } catch (const fs::filesystem_error&) {
  }
  return 0;
}
