// Regenerates the files that follow the LSCENE/LCAP vocabulary
// (generator/lang/vocabulary.cc): the generated tables of docs/languages.md
// and the "definitions/kinds" of schemas/lscene.schema.json and
// lcap.schema.json.
//   vocabulary_print --write REPO     rewrite the three files (atomically)
//   vocabulary_print --check REPO     exit 1 naming each file that differs
//   vocabulary_print TABLE            print one docs table (lscene-symbols, ...)
#include <iostream>
#include <string>

#include "generator/lang/vocabulary_docs.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"

namespace {

struct Followed {
  std::string path;      // relative to the repository
  std::string language;  // schemas only
};
const Followed kFiles[] = {{"docs/languages.md", ""},
                           {"schemas/lscene.schema.json", "LSCENE"},
                           {"schemas/lcap.schema.json", "LCAP"}};

std::string Generated(const Followed& f, const std::string& text) {
  return f.language.empty() ? lsds::UpdateVocabularyDocs(text, f.path)
                            : lsds::UpdateVocabularySchema(text, f.language);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if ((mode == "--write" || mode == "--check") && argc == 3) {
      int differ = 0;
      for (const Followed& f : kFiles) {
        const std::string path = std::string(argv[2]) + "/" + f.path;
        const std::string text = lsds::ReadFile(path);
        const std::string generated = Generated(f, text);
        if (generated == text) continue;
        if (mode == "--write") {
          lsds::WriteFileAtomic(path, generated);
          std::cout << "rewrote " << path << "\n";
        } else {
          std::cerr << path << " differs from the vocabulary (generator/lang/vocabulary.cc)\n";
          ++differ;
        }
      }
      return differ ? 1 : 0;
    }
    if (argc == 2 && mode[0] != '-') {
      std::cout << lsds::VocabularyMarkdown(mode);
      return 0;
    }
    std::cerr << "usage: vocabulary_print --write REPO | --check REPO | TABLE\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 2;
  }
}
