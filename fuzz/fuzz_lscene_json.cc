// libFuzzer target: any byte string fed to the LSCENE/LCAP JSON form (the path
// `lsds plan` and `lsds generate` take for a .json scene) and to the nesting
// pre-scan either parses or throws lsds::Error; it never crashes, hangs, leaks
// or overflows the stack (deep nesting is refused with a located error).
#include <cstddef>
#include <cstdint>
#include <string>

#include "generator/lang/source.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    lsds::SourceFile source = lsds::ParseSource(text, "fuzz.json", true);
    (void)source.doc.dump();  // printing recurses: must stay within the limit
  } catch (const lsds::Error&) {
  }
  return 0;
}
