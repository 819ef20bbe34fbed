// lsds language [--json]
#include <iostream>

#include "generator/lang/vocabulary_json.h"
#include "tools/command.h"

namespace lsds {

int RunLanguage(int argc, char** argv) {
  CLI::App app(
      "Print the LSCENE/LCAP vocabulary: every kind and block, and every key with its other "
      "spellings, value type, unit and range.",
      "lsds language");
  bool json = false;
  app.add_flag("--json", json, "print it as JSON (docs/languages.md, \"Reflection\")");
  CommonFlags common;
  AddCommonFlags(app,
                 &common,
                 "",
                 {{"--frames", "lsds language reads no collection"},
                  {"--force", "lsds language writes no file"}});
  return RunCommand(app, common, argc, argv, [&] {
    if (json) {
      std::cout << VocabularyJson().dump(2) << "\n";
    } else {
      std::cout << VocabularyText();
    }
    return 0;
  });
}

}  // namespace lsds
