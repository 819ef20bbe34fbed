// The defect corpus: named corruptions of a good synthetic collection, each
// with the check id and the location `lsds validate` must report. Used by the
// tests and by the corpus builder (make_bad_corpus.cc, driven by
// scripts/make-bad-corpus.py).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lsds::validate::corpus {

struct Expected {
  std::string check;  // check id
  std::string file;   // location file, relative to the collection root
  std::optional<int64_t> frame;
  std::string json_pointer;  // "" = not asserted
  std::optional<int> pixel_x, pixel_y;
};

struct Corruption {
  std::string name;
  std::string description;
  // Corrupts the collection at `root` in place; returns what the validator must
  // report.
  std::function<Expected(const std::filesystem::path& root)> apply;
};

const std::vector<Corruption>& Corruptions();
const Corruption& FindCorruption(const std::string& name);

// The good collection every corruption starts from: synth::DefaultSpec()
// (64x48, 4 frames).
void WriteGoodCollection(const std::filesystem::path& root);

// Copies a collection folder.
void CopyCollection(const std::filesystem::path& from, const std::filesystem::path& to);

}  // namespace lsds::validate::corpus
