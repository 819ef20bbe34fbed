#include "generator/lang/vocabulary_docs.h"

#include <set>

#include <nlohmann/json.hpp>

#include "generator/lang/vocabulary.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

std::string Code(const std::string& s) { return "`" + s + "`"; }

// "`visible` / `visibility`"
std::string SpellingsCell(const KeySpec& key) {
  std::vector<std::string> parts;
  for (const std::string& s : key.Spellings()) parts.push_back(Code(s));
  return Join(parts, " / ");
}

// "default 100000", "default [0,360]", "default: the class's size" ("" for none)
std::string DefaultText(const KeySpec& key) {
  if (!key.default_text.empty()) return "default: " + key.default_text;
  if (key.default_value.is_null()) return "";
  return "default " + (key.default_value.is_string() ? key.default_value.get<std::string>()
                                                     : key.default_value.dump());
}

// The doc line with the default after it.
std::string DocWithDefault(const KeySpec& key) {
  const std::string by_default = DefaultText(key);
  if (by_default.empty()) return key.doc;
  return key.doc.empty() ? by_default : key.doc + "; " + by_default;
}

std::string RangeText(const KeySpec& key, bool say_whole = true) {
  if (!key.range) return "";
  return key.range->Text(say_whole) + (key.unit.empty() ? "" : " " + key.unit);
}

// "`elevation` (deg above horizon; within [-90, 90] degrees)"
std::string KeyItem(const KeySpec& key) {
  std::vector<std::string> notes;
  if (!key.doc.empty()) notes.push_back(key.doc);
  if (const std::string by_default = DefaultText(key); !by_default.empty())
    notes.push_back(by_default);
  if (key.range) notes.push_back(RangeText(key));
  return SpellingsCell(key) + (notes.empty() ? "" : " (" + Join(notes, "; ") + ")");
}

std::string KindCell(const KindSpec& kind) {
  std::vector<std::string> aliases;
  for (const std::string& a : kind.aliases) aliases.push_back(Code(a));
  std::string cell = Code(kind.id);
  if (!aliases.empty()) cell += " (" + Join(aliases, ", ") + ")";
  if (!kind.category.empty()) cell += " - " + kind.category;
  return cell;
}

std::string KeysCell(const KindSpec& kind) {
  if (!kind.doc.empty()) return kind.doc;
  std::vector<std::string> items;
  for (const KeySpec& k : kind.keys) items.push_back(KeyItem(k));
  return Join(items, "; ");
}

std::string SymbolsTable(const std::string& language) {
  std::string out = "| kind (aliases) - category | keys | example |\n|---|---|---|\n";
  for (const KindSpec& k : Vocabulary())
    if (k.language == language)
      out += "| " + KindCell(k) + " | " + KeysCell(k) + " | " + k.example + " |\n";
  return out;
}

std::string ValueCell(const KeySpec& key) {
  std::string cell = ValueTypeName(key.type);
  if (key.range) cell += ", " + RangeText(key, key.type != ValueType::kWhole);
  return cell;
}

std::string KeysTable(const std::string& id, bool with_examples) {
  std::string out = with_examples ? "| key | value | function | example |\n|---|---|---|---|\n"
                                  : "| key | value | meaning |\n|---|---|---|\n";
  for (const KeySpec& k : KindVocabulary(id).keys) {
    out += "| " + SpellingsCell(k) + " | " + ValueCell(k) + " | " + DocWithDefault(k);
    if (with_examples) out += " | " + k.example;
    out += " |\n";
  }
  return out;
}

// LCAP's Path generators: generator (the paper's name) | its keys | its frames.
std::string GeneratorsTable() {
  std::string out = "| generator | keys | frames |\n|---|---|---|\n";
  for (const KeySpec& k : KindVocabulary("path").keys) {
    const KindSpec& block = KindVocabulary(k.block);
    out += "| " + SpellingsCell(k) + (block.paper.empty() ? "" : " (" + block.paper + ")") + " | " +
           KeysCell(block) + " | " + k.doc + " |\n";
  }
  return out;
}

// The nested blocks reachable from the kinds of `language`, in table order.
std::set<std::string> BlocksOf(const std::string& language) {
  std::set<std::string> blocks;
  bool grew = true;
  while (grew) {
    grew = false;
    for (const KindSpec& kind : Vocabulary()) {
      if (kind.language != language && !blocks.count(kind.id)) continue;
      for (const KeySpec& key : kind.keys)
        if (!key.block.empty()) grew = blocks.insert(key.block).second || grew;
    }
  }
  return blocks;
}

nlohmann::ordered_json KindSchema(const KindSpec& kind) {
  nlohmann::ordered_json s;
  std::string description = kind.what;
  if (!kind.aliases.empty()) description += " (other spellings: " + Join(kind.aliases, ", ") + ")";
  if (!kind.category.empty()) description += "; category " + kind.category;
  if (!kind.doc.empty()) description += ": " + kind.doc;
  s["description"] = description;
  s["type"] = "object";
  if (!kind.keys_listed) return s;
  nlohmann::ordered_json properties = nlohmann::ordered_json::object();
  for (const KeySpec& key : kind.keys) {
    nlohmann::ordered_json p;
    // A default in words is said in the description (JSON Schema's `default` is a value).
    p["description"] = key.default_text.empty() ? key.doc : DocWithDefault(key);
    if (!key.default_value.is_null()) p["default"] = key.default_value;
    std::string value = ValueTypeName(key.type);
    if (key.range) value += ", " + RangeText(key, key.type != ValueType::kWhole);
    if (!key.block.empty()) value += " (definitions/kinds/" + key.block + ")";
    p["$comment"] = value;
    properties[key.name] = p;
    for (const std::string& alias : key.aliases)
      properties[alias] = {{"description", "another spelling of " + key.name}};
  }
  s["properties"] = properties;
  return s;
}

}  // namespace

std::vector<std::string> VocabularyDocTables() {
  return {"lscene-symbols",
          "object-keys",
          "lcap-symbols",
          "camera-settings",
          "capture-settings",
          "path-generators"};
}

std::string VocabularyMarkdown(const std::string& table) {
  if (table == "lscene-symbols") return SymbolsTable("LSCENE");
  if (table == "object-keys") return KeysTable("object", true);
  if (table == "lcap-symbols") return SymbolsTable("LCAP");
  if (table == "camera-settings") return KeysTable("camera_settings", false);
  if (table == "capture-settings") return KeysTable("capture_settings", false);
  if (table == "path-generators") return GeneratorsTable();
  throw Error("no vocabulary table '" + table + "'; known: " + Join(VocabularyDocTables(), ", "));
}

std::string UpdateVocabularyDocs(const std::string& doc, const std::string& path) {
  std::string out = doc;
  for (const std::string& id : VocabularyDocTables()) {
    const std::string open = "<!-- vocabulary:" + id + " -->\n";
    const std::string close = "<!-- /vocabulary:" + id + " -->";
    const size_t begin = out.find(open);
    const size_t end = begin == std::string::npos ? begin : out.find(close, begin);
    if (begin == std::string::npos || end == std::string::npos)
      throw Error(path + ": no generated section '" + open.substr(0, open.size() - 1) + "' ... '" +
                  close + "'");
    out.replace(begin + open.size(), end - begin - open.size(), VocabularyMarkdown(id));
  }
  return out;
}

std::string UpdateVocabularySchema(const std::string& schema_text, const std::string& language) {
  nlohmann::ordered_json schema = nlohmann::ordered_json::parse(schema_text);
  nlohmann::ordered_json kinds = nlohmann::ordered_json::object();
  kinds["description"] =
      "The " + language +
      " vocabulary, generated from generator/lang/vocabulary.cc (do not edit; regenerate with "
      "tests/generator/vocabulary_print --write): each kind's and nested block's keys, their "
      "value and range. Keys match in any spelling of case, '_', ' ' and '-'; the compiler "
      "checks them with did-you-mean suggestions.";
  nlohmann::ordered_json properties = nlohmann::ordered_json::object();
  std::set<std::string> blocks = BlocksOf(language);
  if (language == "LCAP")  // the blocks of collection entries, which no key names
    for (const KindSpec& kind : Vocabulary())
      if (kind.language.empty() && !BlocksOf("LSCENE").count(kind.id)) blocks.insert(kind.id);
  for (const KindSpec& kind : Vocabulary())
    if (kind.language == language || blocks.count(kind.id)) properties[kind.id] = KindSchema(kind);
  kinds["properties"] = properties;
  schema["definitions"]["kinds"] = kinds;
  return schema.dump(2) + "\n";
}

}  // namespace lsds
