#include "generator/lang/source.h"

#include <filesystem>

#include "generator/lang/text_parser.h"
#include "libs/collection/json_stream.h"
#include "libs/util/atomic_file.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "libs/util/limits.h"
#include "libs/util/text_check.h"

namespace lsds {

std::string PointerJoin(const std::string& parent, const std::string& token) {
  std::string escaped;
  for (char c : token) {
    if (c == '~')
      escaped += "~0";
    else if (c == '/')
      escaped += "~1";
    else
      escaped += c;
  }
  return parent + "/" + escaped;
}

Location SourceFile::Where(const std::string& pointer) const {
  if (is_json) return Location(path, pointer.empty() ? "" : pointer);
  std::string p = pointer;
  while (true) {
    auto it = positions.find(p);
    if (it != positions.end()) return Location::Text(path, it->second.first, it->second.second);
    const size_t slash = p.rfind('/');
    if (slash == std::string::npos || p.empty()) break;
    p = p.substr(0, slash);
  }
  return Location::Text(path, 1, 1);
}

Location SourceFile::WhereKey(const std::string& pointer) const {
  auto it = key_positions.find(pointer);
  if (!is_json && it != key_positions.end())
    return Location::Text(path, it->second.first, it->second.second);
  return Where(pointer);
}

SourceFile ParseSource(const std::string& text,
                       const std::string& path_for_messages,
                       bool is_json) {
  SourceFile source;
  source.path = path_for_messages;
  source.text = text;
  source.is_json = is_json;
  // Comments too: the text ends up in JSON (plans, provenance), which holds
  // UTF-8 only.
  CheckUtf8(text, path_for_messages);
  CheckNoNulBytes(text, path_for_messages);
  if (is_json) {
    CheckJsonNesting(text, path_for_messages);
    try {
      source.doc = OJson::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
      throw JsonParseError(text, path_for_messages, e);
    } catch (const nlohmann::json::out_of_range& e) {
      throw JsonParseError(text, path_for_messages, e);
    }
    if (!source.doc.is_object())
      throw Error("expected a JSON object at the top level", Location(path_for_messages, ""));
  } else {
    ParseTextNotation(&source);
  }
  return source;
}

SourceFile LoadSource(const std::string& path) {
  const std::string text = ReadTextFile(path);
  bool is_json = std::filesystem::path(path).extension() == ".json";
  if (!is_json) {
    const size_t first = text.find_first_not_of(" \t\r\n");
    is_json = first != std::string::npos && text[first] == '{';
  }
  return ParseSource(text, path, is_json);
}

}  // namespace lsds
