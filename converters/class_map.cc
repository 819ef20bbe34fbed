#include "converters/class_map.h"

#include <algorithm>
#include <filesystem>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::convert {

namespace {

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

}  // namespace

ClassMap ClassMap::All(const std::vector<ClassInfo>& classes) {
  std::vector<ClassInfo> sorted = classes;
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  ClassMap map;
  for (const ClassInfo& c : sorted) {
    map.index_[c.id] = static_cast<int>(map.classes_.size());
    map.classes_.push_back({c.name, {c.id}});
  }
  return map;
}

ClassMap ClassMap::Parse(const std::string& spec, const std::vector<ClassInfo>& classes) {
  std::vector<std::string> entries;
  std::string where = "--classes";
  std::error_code ec;
  if (std::filesystem::is_regular_file(spec, ec)) {
    where = spec;
    for (const std::string& line : Split(ReadFile(spec), '\n')) {
      const std::string entry = Trim(line.substr(0, line.find('#')));
      if (!entry.empty()) entries.push_back(entry);
    }
  } else {
    for (const std::string& part : Split(spec, ',')) {
      const std::string entry = Trim(part);
      if (!entry.empty()) entries.push_back(entry);
    }
  }
  if (entries.empty()) throw Error("no classes selected", Location(where));
  std::vector<std::string> names;
  names.reserve(classes.size());
  for (const ClassInfo& c : classes) names.push_back(c.name);

  ClassMap map;
  for (const std::string& entry : entries) {
    const size_t eq = entry.find('=');
    const std::string source = Trim(entry.substr(0, eq));
    const std::string target = eq == std::string::npos ? source : Trim(entry.substr(eq + 1));
    const ClassInfo* found = nullptr;
    for (const ClassInfo& c : classes) {
      if (c.name == source || std::to_string(c.id) == source) found = &c;
    }
    if (found == nullptr) {
      throw Error("unknown class '" + source + "'" + DidYouMean(source, names), Location(where));
    }
    if (target.empty()) throw Error("empty class name in '" + entry + "'", Location(where));
    const std::string name = eq == std::string::npos ? found->name : target;
    if (map.index_.count(found->id)) {
      throw Error("class '" + source + "' listed twice", Location(where));
    }
    auto it = std::find_if(map.classes_.begin(), map.classes_.end(), [&](const OutputClass& o) {
      return o.name == name;
    });
    if (it == map.classes_.end()) {
      map.classes_.push_back({name, {}});
      it = map.classes_.end() - 1;
    }
    it->source_ids.push_back(found->id);
    map.index_[found->id] = static_cast<int>(it - map.classes_.begin());
  }
  return map;
}

std::optional<int> ClassMap::Map(uint32_t class_id) const {
  const auto it = index_.find(class_id);
  if (it == index_.end()) return std::nullopt;
  return it->second;
}

ClassMap ClassMap::OnlyUsed(const std::set<uint32_t>& used) const {
  ClassMap map;
  for (const OutputClass& c : classes_) {
    const bool seen = std::any_of(
        c.source_ids.begin(), c.source_ids.end(), [&](uint32_t id) { return used.count(id); });
    if (!seen) continue;
    // Every source of a merged class keeps it, seen or not: the class is one.
    for (uint32_t id : c.source_ids) map.index_[id] = static_cast<int>(map.classes_.size());
    map.classes_.push_back(c);
  }
  return map;
}

}  // namespace lsds::convert
