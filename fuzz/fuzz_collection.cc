// libFuzzer target: any byte string as collection.json goes through what
// `lsds info` does (SummarizeCollection: the read-once path and, where it
// falls back, CollectionReader; both summaries) and, as
// metadata.json, through MetadataReader (perturb-metadata, backproject
// --use-metadata): each reads or throws lsds::Error naming the file and the
// place; never a crash, leak, hang or stack overflow.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz/fuzz_input.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/summary.h"
#include "libs/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path root = lsds::fuzz::ScratchDir() / "C";
  std::filesystem::create_directories(root);
  lsds::fuzz::WriteBytes(root / lsds::kCollectionFile, data, size);
  try {
    const lsds::CollectionInfo info = lsds::SummarizeCollection(root);
    (void)lsds::SummaryToJson(info).dump();
    (void)lsds::SummaryToText(info);
  } catch (const lsds::Error&) {
  } catch (const std::filesystem::filesystem_error&) {  // exit 2 in the CLI as well
  }
  lsds::fuzz::WriteBytes(root / lsds::kMetadataFile, data, size);
  try {
    const lsds::MetadataReader metadata(root / lsds::kMetadataFile);
    size_t frames = 0;
    metadata.ForEachFrame([&](const lsds::MetadataFrame&) { ++frames; });
  } catch (const lsds::Error&) {
  }
  return 0;
}
