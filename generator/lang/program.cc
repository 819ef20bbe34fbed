#include "generator/lang/scene.h"

#include <cctype>

#include "generator/lang/vocabulary.h"
#include "libs/util/strings.h"

namespace lsds {

const std::map<std::string, std::string>& CategoryKinds() {
  static const std::map<std::string, std::string> kinds = [] {
    std::map<std::string, std::string> out;
    for (const KindSpec& k : Vocabulary())
      if (!k.category.empty()) out[k.category] = k.id;
    return out;
  }();
  return kinds;
}

const Definition* Program::Find(const std::string& symbol) const {
  for (const Definition& d : definitions)
    if (d.symbol == symbol) return &d;
  return nullptr;
}

Program ReadProgram(const SourceFile& src, const std::string& start) {
  Program program;
  program.src = &src;
  program.start = start;
  const Node root{&src, &src.doc, ""};
  const std::string other = start == "LSCENE" ? "LCAP" : "LSCENE";
  const std::vector<std::string> kind_names = KindSpellings();
  for (const auto& [key, node] : root.Members()) {
    if (key == start) {
      if (!node->is_array()) node.Fail(start + " must be a list of ONE(...)/MANY(...) entries");
      program.start_rule = node;
      continue;
    }
    if (key == other)
      node.Fail("this is " + other + " notation but a" +
                (start == "LSCENE" ? " scene" : " capture") +
                " file was expected (scene first, capture second)");
    if (key.empty() || !(std::isalpha(static_cast<unsigned char>(key[0])) || key[0] == '_'))
      node.Fail("symbol names start with a letter, found '" + key + "'");
    if (!node->is_object() || node->size() != 1)
      node.Fail(
          "a definition is {\"KIND\": {...}} with exactly one kind (skybox, "
          "terrain, object, camera, path, ...)");
    const auto [kind_key, body] = node.Members().front();
    const std::string kind = KindOfSpelling(CanonicalKey(kind_key));
    if (kind.empty())
      body.Fail("unknown kind '" + kind_key + "' for " + key +
                DidYouMean(CanonicalKey(kind_key), kind_names));
    if (!body->is_object()) body.Fail("the body of " + key + " must be {key: value, ...}");
    Definition def;
    def.symbol = key;
    def.kind = kind;
    def.body = body;
    def.statement = node;
    def.order = program.definitions.size();
    program.definitions.push_back(def);
  }
  return program;
}

}  // namespace lsds
