// libFuzzer target: `lsds import FORMAT` (ImportCollection) on a small real
// source whose main metadata file is the input. The source is the import
// fixture of FORMAT (LSDS_FUZZ_SOURCE: a folder written by
// write_import_fixture, copied once); LSDS_FUZZ_FORMAT and LSDS_FUZZ_FILE (the
// file the input replaces, relative to the source) are compile definitions, one
// binary per importer. Every input is imported or refused with lsds::Error (or
// a std::filesystem error: exit 2 in the CLI as well); never a crash, another
// exception (exit 70), a hang, or a read outside the source.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include "fuzz/fuzz_input.h"
#include "importers/import_collection.h"
#include "libs/util/error.h"

namespace fs = std::filesystem;

namespace {

fs::path Source() {
  static const fs::path root = [] {
    fs::path dir = lsds::fuzz::ScratchDir() / "source";
    fs::create_directories(dir);
    // NOLINTNEXTLINE(concurrency-mt-unsafe): lsds never sets the environment
    if (const char* source = std::getenv("LSDS_FUZZ_SOURCE"))
      fs::copy(source, dir, fs::copy_options::recursive);
    return dir;
  }();
  return root;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path source = Source();
  const fs::path file = source / LSDS_FUZZ_FILE;
  fs::create_directories(file.parent_path());
  lsds::fuzz::WriteBytes(file, data, size);
  // BOP's scene folder is two levels down its dataset (models/ beside the
  // splits); the others are the folder itself.
  const fs::path scene =
      std::string(LSDS_FUZZ_FORMAT) == "bop" ? source / "train_pbr" / "000000" : source;
  const fs::path output = lsds::fuzz::ScratchDir() / "out";
  try {
    (void)lsds::import::ImportCollection(LSDS_FUZZ_FORMAT, scene, output, {}, true);
  } catch (const lsds::Error&) {
  } catch (const fs::filesystem_error&) {
  }
  std::error_code ignored;
  fs::remove_all(output, ignored);
  return 0;
}
