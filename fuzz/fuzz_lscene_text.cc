// libFuzzer target: any byte string fed to the LSCENE/LCAP text parser either
// parses or throws lsds::Error; it never crashes, hangs or reads out of bounds.
#include <cstddef>
#include <cstdint>
#include <string>

#include "generator/lang/source.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    lsds::SourceFile source = lsds::ParseSource(text, "fuzz.lscene", false);
    for (const auto& [pointer, position] : source.positions) (void)source.Where(pointer);
  } catch (const lsds::Error&) {
  }
  return 0;
}
