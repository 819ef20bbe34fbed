#include "generator/lang/vocabulary_json.h"

#include <cmath>
#include <sstream>

#include "generator/lang/vocabulary.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

constexpr ValueType kValueTypes[] = {ValueType::kNumber,
                                     ValueType::kWhole,
                                     ValueType::kCount,
                                     ValueType::kBool,
                                     ValueType::kName,
                                     ValueType::kColor,
                                     ValueType::kVector2,
                                     ValueType::kVector3,
                                     ValueType::kScale,
                                     ValueType::kReference,
                                     ValueType::kClass,
                                     ValueType::kDate,
                                     ValueType::kTime,
                                     ValueType::kList,
                                     ValueType::kBlock,
                                     ValueType::kNumberOrBlock,
                                     ValueType::kAny};

// A range as numbers a program can check against, and the parser's own words
// for it. An unbounded end is left out (JSON has no infinity).
nlohmann::ordered_json RangeJson(const Range& range) {
  nlohmann::ordered_json out = {{"min", range.lo}, {"min_excluded", range.lo_open}};
  if (std::isfinite(range.hi)) out["max"] = range.hi;
  out["whole"] = range.whole;
  out["text"] = range.Text();
  if (!range.note.empty()) out["note"] = range.note;
  return out;
}

void PutIfSet(nlohmann::ordered_json& out, const char* name, const std::string& value) {
  if (!value.empty()) out[name] = value;
}

nlohmann::ordered_json KeyJson(const KeySpec& key) {
  nlohmann::ordered_json out = {
      {"name", key.name}, {"aliases", key.aliases}, {"type", ValueTypeName(key.type)}};
  PutIfSet(out, "unit", key.unit);
  if (key.range) out["range"] = RangeJson(*key.range);
  PutIfSet(out, "block", key.block);
  PutIfSet(out, "role", key.role);
  if (!key.default_value.is_null()) out["default"] = key.default_value;
  // A default that depends on the context, in words ("the class's size").
  PutIfSet(out, "default_text", key.default_text);
  // An environment key an LCAP scene change may not set (the others may).
  if (!key.in_change) out["in_change"] = false;
  PutIfSet(out, "doc", key.doc);
  return out;
}

}  // namespace

nlohmann::ordered_json VocabularyJson() {
  nlohmann::ordered_json types = nlohmann::ordered_json::array();
  for (const ValueType type : kValueTypes) types.push_back(ValueTypeName(type));
  nlohmann::ordered_json kinds = nlohmann::ordered_json::array();
  for (const KindSpec& kind : Vocabulary()) {
    nlohmann::ordered_json entry = {{"id", kind.id}, {"aliases", kind.aliases}};
    // A nested block (`clouds`, camera settings) belongs to no language of its own.
    PutIfSet(entry, "language", kind.language);
    PutIfSet(entry, "category", kind.category);
    PutIfSet(entry, "what", kind.what);
    PutIfSet(entry, "paper", kind.paper);
    entry["keys_listed"] = kind.keys_listed;
    nlohmann::ordered_json keys = nlohmann::ordered_json::array();
    for (const KeySpec& key : kind.keys) keys.push_back(KeyJson(key));
    entry["keys"] = std::move(keys);
    PutIfSet(entry, "doc", kind.doc);
    kinds.push_back(std::move(entry));
  }
  return {{"format", "lsds-language"},
          {"format_version", 1},
          {"value_types", std::move(types)},
          {"kinds", std::move(kinds)}};
}

std::string VocabularyText() {
  std::ostringstream out;
  for (const KindSpec& kind : Vocabulary()) {
    out << (kind.language.empty() ? "block" : kind.language) << " " << kind.id;
    if (!kind.aliases.empty()) out << " (also " << Join(kind.aliases, ", ") << ")";
    out << "\n";
    for (const KeySpec& key : kind.keys) {
      out << "  " << key.name << ": " << ValueTypeName(key.type);
      if (key.range) out << ", " << key.range->Text();
      if (!key.unit.empty()) out << " " << key.unit;
      if (!key.default_value.is_null()) out << ", default " << key.default_value.dump();
      if (!key.default_text.empty()) out << ", default: " << key.default_text;
      if (!key.aliases.empty()) out << " (also " << Join(key.aliases, ", ") << ")";
      out << "\n";
    }
  }
  return out.str();
}

}  // namespace lsds
