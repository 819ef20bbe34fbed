// The output classes of a conversion: which collection classes are kept, under
// which name, in which order (0-based output index = position in that order;
// YOLO names and COCO category ids follow it).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "libs/collection/model.h"

namespace lsds::convert {

struct OutputClass {
  std::string name;
  std::vector<uint32_t> source_ids;  // collection class ids merged into this one
};

class ClassMap {
 public:
  // Every class of the collection's class table, in increasing id order, under
  // its own name.
  static ClassMap All(const std::vector<ClassInfo>& classes);
  // `spec` is a file (one entry per line, '#' comments) or a comma list; each
  // entry is `SOURCE` or `SOURCE=NAME`, SOURCE a class name or id of the
  // collection. Several sources with the same NAME are merged; classes not
  // listed are dropped; output order = first appearance of each NAME.
  static ClassMap Parse(const std::string& spec, const std::vector<ClassInfo>& classes);

  // The output classes that have at least one source id in `used`, in the
  // same order, re-indexed 0..K-1 (docs/convert.md, "Classes"). Classes that
  // no kept object has are not listed, so YOLO ids stay contiguous.
  ClassMap OnlyUsed(const std::set<uint32_t>& used) const;

  // 0-based output index of a collection class id, none when the class is not
  // kept.
  std::optional<int> Map(uint32_t class_id) const;
  const std::vector<OutputClass>& classes() const { return classes_; }

 private:
  std::vector<OutputClass> classes_;
  std::map<uint32_t, int> index_;
};

}  // namespace lsds::convert
