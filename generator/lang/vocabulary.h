// The vocabulary of LSCENE and LCAP: one table per kind of definition (and per
// nested block such as `clouds` or camera settings) with each function's
// canonical name, its other accepted spellings, value type, range and doc
// line. The parser's key checks, alias resolution and range checks, the
// keys part of schemas/lscene.schema.json and lcap.schema.json, and the
// tables of docs/languages.md are all read from here (vocabulary_docs.h
// prints the last two; tests/generator/vocabulary_test.cc keeps the committed
// files equal to them). Adding a function = one row here + its semantics
// where the kind is evaluated (docs/languages.md, "The vocabulary table").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "generator/lang/random.h"
#include "generator/lang/values.h"

namespace lsds {

// What a key's value is (docs/languages.md, "Values"); `sampled` types take
// every value form (crisp, choice, interval, distribution).
enum class ValueType {
  kNumber,         // sampled number
  kWhole,          // crisp whole number
  kCount,          // whole number >= 0, sampled (interval inclusive)
  kBool,           // sampled true/false
  kName,           // sampled name
  kColor,          // colour name or [r, g, b]
  kVector2,        // [x, y], sampled per component
  kVector3,        // [x, y, z], sampled per component, or a vector range
  kScale,          // a scalar for all axes or a vector
  kReference,      // the symbol of another definition
  kClass,          // a class, a choice of classes or an asset selection
  kDate,           // "YYYY-MM-DD"
  kTime,           // "HH:MM" or "HH:MM:SS"
  kList,           // [a, b, ...]
  kBlock,          // {key: value, ...}: a nested table (KeySpec::block)
  kNumberOrBlock,  // a number or a nested table
  kAny,            // several forms, described in the doc line
};
const char* ValueTypeName(ValueType type);

// The values a key accepts; a sampled value outside is a located error
// naming the range ("elevation must be within [-90, 90] degrees, sampled 95").
struct Range {
  double lo = 0;
  double hi = 0;         // +infinity: no upper bound
  bool lo_open = false;  // (lo, hi]: lo itself refused
  bool whole = false;    // whole numbers only
  std::string note;      // appended to the message ("write 10 % as 0.1")
  bool Contains(double v) const;
  // "within [-90, 90]", ">= 0", "> 0", "a whole number within [0, 10]"
  // (`say_whole`: false leaves out "a whole number").
  std::string Text(bool say_whole = true) const;
};

struct KeySpec {
  std::string name;                  // canonical spelling, snake_case
  std::vector<std::string> aliases;  // other spellings of the same function
  ValueType type = ValueType::kAny;
  std::optional<Range> range;
  std::string unit;       // of the range and value ("degrees", "m", "lux")
  std::string doc;        // the doc line (markdown)
  std::string example;    // for the docs' key tables (markdown, optional)
  std::string block;      // kBlock / kNumberOrBlock: the id of the nested table
  bool in_change = true;  // environment kinds: also callable in an LCAP scene change
  std::string role;       // a group within the kind ("target quantity", "frame quantity")
  // The value without the key, when it is a literal (null otherwise). Docs, schemas and `lsds
  // language --json` print it; tests/lang/vocabulary_defaults_test.cc holds it equal to the
  // evaluators' own.
  nlohmann::json default_value;
  // A default that depends on the context, in words ("the class's size", "derived from --seed"),
  // printed where a literal default is; the same test holds it to the evaluators'.
  std::string default_text;

  std::vector<std::string> Spellings() const;  // name, then aliases
};

struct KindSpec {
  std::string id;                    // canonical kind ("skybox") or block id ("clouds")
  std::string language;              // "LSCENE", "LCAP", or "" for a nested block
  std::vector<std::string> aliases;  // other spellings of the kind ("sky")
  std::string category;              // Table 1/3 category symbol ("S"), if any
  std::string what;                  // for messages ("terrain height")
  std::string doc;                   // the docs' keys cell when the keys are not listed
  std::string example;               // markdown
  bool keys_listed = true;           // false: the keys are checked in the kind's code
  std::vector<KeySpec> keys;
  std::string paper;  // the paper's name of a generator block ("Create Hemi")

  // nullptr when `canonical` (CanonicalKey form) names no key of the kind.
  const KeySpec* Find(const std::string& canonical) const;
  const KeySpec& Key(const std::string& name) const;  // by canonical name; must exist
  // The canonical names of the keys with `role`, in table order.
  std::vector<std::string> KeysWithRole(const std::string& role) const;
  // Every key's spellings in table order (for the unknown-key check).
  std::vector<std::string> Spellings(bool in_change = false) const;
};

// Every table: the LSCENE kinds, the LCAP kinds, then the nested blocks.
const std::vector<KindSpec>& Vocabulary();
// The table of a kind or block by id; throws std::out_of_range for none.
const KindSpec& KindVocabulary(const std::string& id);
// The canonical kind of a spelling of a kind ("sky" -> "skybox"), "" if none.
std::string KindOfSpelling(const std::string& canonical_spelling);
// Every kind spelling (canonical form) for suggestions.
std::vector<std::string> KindSpellings();

// Checks the members of `body` against `kind`: an unknown key is a located
// error with a suggestion (did you mean ...?), two spellings of one key given
// together are a located error. `what` names the place ("object O1").
void CheckKeys(const Node& body,
               const KindSpec& kind,
               const std::string& what,
               bool in_change = false);

// The member giving `key` of `kind` under any of its spellings (a null Node
// when absent).
Node FindKey(const Node& body, const KindSpec& kind, const std::string& key);

// Checks `value`, read from `node`, against the key's range (if any): a
// located error naming the range when outside.
double CheckRange(const Node& node, const KeySpec& key, double value);
// SampleScalar, then CheckRange.
double SampleInRange(const Node& node, const KeySpec& key, Rng& rng);
// ReadNumber (crisp), then CheckRange.
double ReadInRange(const Node& node, const KeySpec& key);

}  // namespace lsds
