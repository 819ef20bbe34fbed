// `lsds language --json` (docs/languages.md, "Reflection") checked against the
// parser: every kind and key it lists, under every spelling it gives, is one the
// parser accepts, and every range it gives is the one the parser enforces.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "generator/lang/source.h"
#include "generator/lang/values.h"
#include "generator/lang/vocabulary.h"
#include "libs/util/error.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

nlohmann::json LanguageJson() {
  const testing::CommandResult result = testing::RunLsds("language --json");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return nlohmann::json::parse(result.output);
}

// The parser's own range check on the number `value` given to `key`.
bool Accepted(const KeySpec& key, double value) {
  nlohmann::ordered_json doc;
  doc["k"] = value;
  const SourceFile src = ParseSource(doc.dump(), "v.json", true);
  try {
    ReadInRange(Node{&src, &src.doc["k"], "/k"}, key);
    return true;
  } catch (const Error& e) {
    EXPECT_NE(e.message().find(key.name + " must be " + key.range->Text()), std::string::npos)
        << e.message();
    return false;
  }
}

TEST(LanguageJson, EveryKindAndKeySpellingIsOneTheParserAccepts) {
  const nlohmann::json language = LanguageJson();
  EXPECT_EQ(language["format"], "lsds-language");
  ASSERT_EQ(language["kinds"].size(), Vocabulary().size());
  size_t spellings = 0;
  for (const nlohmann::json& entry : language["kinds"]) {
    const std::string id = entry["id"];
    const KindSpec& kind = KindVocabulary(id);  // throws for a kind the parser does not know
    if (entry.contains("language")) {
      EXPECT_EQ(KindOfSpelling(CanonicalKey(id)), id);
      for (const std::string alias : entry["aliases"])
        EXPECT_EQ(KindOfSpelling(CanonicalKey(alias)), id) << alias;
    }
    ASSERT_EQ(entry["keys"].size(), kind.keys.size()) << id;
    for (const nlohmann::json& key : entry["keys"]) {
      std::vector<std::string> names = {key["name"].get<std::string>()};
      for (const std::string alias : key["aliases"]) names.push_back(alias);
      for (const std::string& name : names) {
        nlohmann::ordered_json doc;
        doc["k"][name] = 1;
        const SourceFile src = ParseSource(doc.dump(), "v.json", true);
        const Node body{&src, &src.doc["k"], "/k"};
        EXPECT_NO_THROW(CheckKeys(body, kind, kind.what)) << id << ": " << name;
        EXPECT_TRUE(FindKey(body, kind, key["name"])) << id << ": " << name;
        ++spellings;
      }
    }
  }
  size_t table_spellings = 0;
  for (const KindSpec& kind : Vocabulary())
    for (const KeySpec& key : kind.keys) table_spellings += key.Spellings().size();
  EXPECT_EQ(spellings, table_spellings);
}

TEST(LanguageJson, EveryRangeIsTheOneTheParserEnforces) {
  const nlohmann::json language = LanguageJson();
  size_t ranges = 0;
  for (const nlohmann::json& entry : language["kinds"]) {
    const KindSpec& kind = KindVocabulary(entry["id"]);
    for (const nlohmann::json& key : entry["keys"]) {
      if (!key.contains("range")) continue;
      const KeySpec& spec = kind.Key(key["name"]);
      const nlohmann::json& range = key["range"];
      const double min = range["min"];
      const double step = range["whole"].get<bool>() ? 1.0 : 0.5;
      EXPECT_EQ(Accepted(spec, min), !range["min_excluded"].get<bool>()) << key["name"];
      EXPECT_FALSE(Accepted(spec, min - step)) << key["name"];
      if (range.contains("max")) {
        const double max = range["max"];
        EXPECT_TRUE(Accepted(spec, max)) << key["name"];
        // (A bound near 2^64, the seed's, has no double just above it a step away.)
        const double above = max + step > max ? max + step : std::nextafter(max, INFINITY);
        EXPECT_FALSE(Accepted(spec, above)) << key["name"];
      } else {
        EXPECT_TRUE(Accepted(spec, std::max(min, 0.0) + 1e9)) << key["name"];
      }
      ++ranges;
    }
  }
  size_t table_ranges = 0;
  for (const KindSpec& kind : Vocabulary())
    for (const KeySpec& key : kind.keys) table_ranges += key.range ? 1 : 0;
  EXPECT_EQ(ranges, table_ranges);
}

TEST(LanguageText, ListsEveryKindWithItsKeys) {
  const testing::CommandResult result = testing::RunLsds("language");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const KindSpec& kind : Vocabulary()) {
    const std::string heading = (kind.language.empty() ? "block" : kind.language) + " " + kind.id;
    EXPECT_NE(result.output.find(heading), std::string::npos) << kind.id;
    if (!kind.keys.empty())
      EXPECT_NE(result.output.find("  " + kind.keys.front().name + ": "), std::string::npos)
          << kind.id;
  }
}

}  // namespace
}  // namespace lsds
