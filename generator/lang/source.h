// An LSCENE or LCAP input, in either notation, as one generic tree (ordered
// JSON: file order matters, definitions are evaluated in the order written)
// plus where each node came from.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/util/error.h"

namespace lsds {

using OJson = nlohmann::ordered_json;

struct SourceFile {
  std::string path;      // as given, for messages
  std::string text;      // verbatim
  bool is_json = false;  // JSON form (locations are JSON pointers) or text notation
  OJson doc;             // {"LSCENE": [...], "S": {"skybox": {...}}, ...}
  std::map<std::string, std::pair<int, int>> positions;      // text: JSON pointer -> (line, column)
  std::map<std::string, std::pair<int, int>> key_positions;  // text: member pointer -> its key
  std::vector<std::string> warnings;                         // accepted deviations (paper typos)

  // Where the node at `pointer` is: "file:line:col" for text (nearest enclosing
  // node with a position), "file#pointer" for JSON.
  Location Where(const std::string& pointer) const;
  // Where the key of the member at `pointer` is (text), else Where(pointer).
  Location WhereKey(const std::string& pointer) const;
};

// Reads `path`: JSON form when it ends in .json or starts with '{', else the
// text notation.
SourceFile LoadSource(const std::string& path);
// Same from memory (the fuzzer and the tests).
SourceFile ParseSource(const std::string& text, const std::string& path_for_messages, bool is_json);

// JSON pointer of `parent` + "/" + escaped `token`.
std::string PointerJoin(const std::string& parent, const std::string& token);

}  // namespace lsds
