// lsds_make_bad_corpus OUT [--only NAME ...] [--list]: writes OUT/good (a
// synthetic collection) and one corrupted copy per corruption, OUT/NAME, plus
// OUT/manifest.json naming the check and location each must be reported at.
// Driven by scripts/make-bad-corpus.py.
#include <cstring>
#include <iostream>
#include <set>

#include <nlohmann/json.hpp>

#include "libs/util/atomic_file.h"
#include "tests/validate/corruptions.h"

namespace fs = std::filesystem;
using namespace lsds::validate::corpus;

int main(int argc, char** argv) {
  std::string out;
  std::set<std::string> only;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--list") == 0) {
      for (const Corruption& c : Corruptions())
        std::cout << c.name << "\t" << c.description << "\n";
      return 0;
    } else if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
      only.insert(argv[++i]);
    } else if (out.empty() && argv[i][0] != '-') {
      out = argv[i];
    } else {
      std::cerr << "usage: lsds_make_bad_corpus OUT [--only NAME ...] [--list]\n";
      return 2;
    }
  }
  if (out.empty()) {
    std::cerr << "usage: lsds_make_bad_corpus OUT [--only NAME ...] [--list]\n";
    return 2;
  }
  try {
    if (fs::exists(out) && !fs::is_empty(out)) {
      std::cerr << out << ": exists and is not empty\n";
      return 2;
    }
    const fs::path good = fs::path(out) / "good";
    WriteGoodCollection(good);
    nlohmann::json manifest = nlohmann::json::array();
    for (const Corruption& c : Corruptions()) {
      if (!only.empty() && only.count(c.name) == 0) continue;
      const fs::path target = fs::path(out) / c.name;
      CopyCollection(good, target);
      const Expected e = c.apply(target);
      nlohmann::json expected = {{"check", e.check}, {"file", e.file}};
      if (e.frame) expected["frame"] = *e.frame;
      if (!e.json_pointer.empty()) expected["json_pointer"] = e.json_pointer;
      if (e.pixel_x) expected["pixel"] = {*e.pixel_x, *e.pixel_y};
      manifest.push_back(
          {{"name", c.name}, {"description", c.description}, {"expected", expected}});
    }
    lsds::WriteFileAtomic(fs::path(out) / "manifest.json", manifest.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::cerr << "lsds_make_bad_corpus: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
