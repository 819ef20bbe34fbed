// The LSCENE/LCAP vocabulary table (generator/lang/vocabulary.h) drives the
// parser's key checks, alias resolution and range checks, the keys part of
// the JSON schemas and the tables of docs/languages.md.
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "generator/lang/planner.h"
#include "generator/lang/source.h"
#include "generator/lang/vocabulary.h"
#include "generator/lang/vocabulary_docs.h"
#include "generator/plan/plan_json.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tests/build_paths.h"
#include "tests/lang/plan_text.h"

namespace lsds {
namespace {

const std::string kRoot = ::lsds::testing::SourceDir();
const std::string kRegenerate = "regenerate with: " + ::lsds::testing::BinaryDir() +
                                "/tests/generator/vocabulary_print --write " + kRoot;

using testing::PlanErrorOf;

// The plan without its copy of the scene text.
std::string PlanOf(const std::string& scene) {
  nlohmann::json plan =
      PlanToJson(MakePlanFromSources(ParseSource(scene, "s.lscene", false), nullptr, 5));
  plan.erase("scene_source");
  return plan.dump();
}

// The spellings a user may write of `s`: as listed, upper case, words split by
// spaces ("on overlap") and joined in camel case ("OnOverlap").
std::vector<std::string> Variants(const std::string& s) {
  std::string upper, spaced, camel;
  bool next_upper = true;
  for (char c : s) {
    upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    spaced += c == '_' ? ' ' : c;
    if (c == '_') {
      next_upper = true;
      continue;
    }
    camel += next_upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    next_upper = false;
  }
  return {s, upper, spaced, camel};
}

TEST(Vocabulary, EverySpellingOfEveryKeyFindsItsEntry) {
  size_t checked = 0;
  for (const KindSpec& kind : Vocabulary()) {
    for (const KeySpec& key : kind.keys) {
      for (const std::string& spelling : key.Spellings()) {
        for (const std::string& variant : Variants(spelling)) {
          nlohmann::ordered_json doc;
          doc["k"][variant] = 1;
          SourceFile src = ParseSource(doc.dump(), "v.json", true);
          const Node body{&src, &src.doc["k"], "/k"};
          EXPECT_NO_THROW(CheckKeys(body, kind, kind.what)) << kind.id << ": " << variant;
          EXPECT_EQ(kind.Find(CanonicalKey(variant)), &key) << kind.id << ": " << variant;
          const Node found = FindKey(body, kind, key.name);
          ASSERT_TRUE(found) << kind.id << ": " << variant;
          EXPECT_EQ(found.pointer, "/k/" + variant);
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 300u);
}

TEST(Vocabulary, NoSpellingBelongsToTwoKeysOfAKind) {
  for (const KindSpec& kind : Vocabulary()) {
    std::set<std::string> seen;
    for (const std::string& s : kind.Spellings())
      EXPECT_TRUE(seen.insert(CanonicalKey(s)).second) << kind.id << ": " << s;
  }
  std::set<std::string> kinds;
  for (const KindSpec& kind : Vocabulary()) {
    if (kind.language.empty()) continue;
    EXPECT_EQ(KindOfSpelling(CanonicalKey(kind.id)), kind.id);
    for (const std::string& a : kind.aliases) EXPECT_EQ(KindOfSpelling(CanonicalKey(a)), kind.id);
  }
}

TEST(Vocabulary, KindSpellingsParseToTheKind) {
  // Every spelling of every LSCENE kind reaches that kind's key check: an
  // unknown key names the kind's table.
  for (const KindSpec& kind : Vocabulary()) {
    if (kind.language != "LSCENE" || !kind.keys_listed) continue;
    std::vector<std::string> spellings = {kind.id};
    spellings.insert(spellings.end(), kind.aliases.begin(), kind.aliases.end());
    for (const std::string& s : spellings) {
      const std::string message = PlanErrorOf("LSCENE = ONE(X)\nX = " + s + "{zzqq:1}\n");
      EXPECT_NE(message.find("unknown key 'zzqq'"), std::string::npos) << s << ": " << message;
      EXPECT_NE(message.find("known keys: " + Join(kind.Spellings(), ", ")), std::string::npos)
          << s << ": " << message;
    }
  }
}

TEST(Vocabulary, AliasesGiveTheSamePlan) {
  const std::string head = "LSCENE = ONE(W) ONE(O) ONE(A)\nW = terrain{size:[40,40]}\n";
  EXPECT_EQ(PlanOf(head + "O = object{class:cube,visible:false,position:{ON:W}}\nA = "
                          "atmosphere{fog:0.01}\n"),
            PlanOf(head + "O = object{class:cube,Visibility:false,position:{on:W}}\nA = "
                          "atmosphere{fog density:0.01}\n"));
  EXPECT_NE(PlanOf(head + "O = object{class:cube,visible:false,position:{ON:W}}\nA = "
                          "atmosphere{fog:0.01}\n"),
            PlanOf(head + "O = object{class:cube,position:{ON:W}}\nA = atmosphere{fog:0.01}\n"));
}

TEST(Vocabulary, TwoSpellingsOfOneKeyAreALocatedError) {
  const std::string line = "O = object{class:cube,visible:true,visibility:false}";
  const std::string message =
      PlanErrorOf("LSCENE = ONE(W) ONE(O)\nW = terrain{size:[40,40]}\n" + line + "\n");
  const std::string expected = "s.lscene:3:" + std::to_string(line.find("visibility") + 1) +
                               ": 'visibility' and 'visible' are two spellings of visible";
  EXPECT_NE(message.find(expected), std::string::npos) << message;
}

TEST(Vocabulary, UnknownKeysSuggestFromTheTable) {
  EXPECT_NE(PlanErrorOf("LSCENE = ONE(G)\nG = georeference{latitude:1,longitud:2}\n")
                .find("s.lscene:2:29: unknown key 'longitud' in G (did you mean 'longitude'?)"),
            std::string::npos);
  EXPECT_NE(PlanErrorOf("LSCENE = ONE(W)\nW = terrain{height:{perlinn:1}}\n")
                .find("s.lscene:2:21: unknown key 'perlinn' in terrain height (did you mean "
                      "'perlin'?)"),
            std::string::npos);
}

// A value just outside the range the table states, as LSCENE text.
std::string Outside(const Range& r) {
  if (r.whole) return FormatNumber(r.lo + 0.5);
  if (std::isfinite(r.lo)) return FormatNumber(r.lo - 1, 17);
  return FormatNumber(r.hi + 1, 17);
}

TEST(Vocabulary, OutOfRangeValuesAreLocatedErrorsNamingTheRange) {
  size_t checked = 0;
  for (const KindSpec& kind : Vocabulary()) {
    if (kind.language != "LSCENE") continue;
    for (const KeySpec& key : kind.keys) {
      if (!key.range || (key.type != ValueType::kNumber && key.type != ValueType::kWhole)) continue;
      std::string body;
      if (kind.id == "object") body = "class:cube,";
      if (kind.id == "georeference") body = key.name == "latitude" ? "longitude:0," : "latitude:0,";
      const std::string prefix = "X = " + kind.id + "{" + body + key.name + ":";
      const std::string scene = "LSCENE = ONE(X)\n" + prefix + Outside(*key.range) + "}\n";
      const std::string message = PlanErrorOf(scene);
      const std::string where = "s.lscene:2:" + std::to_string(prefix.size() + 1) + ": ";
      const std::string expected = where + key.name + " must be " + key.range->Text();
      EXPECT_NE(message.find(expected), std::string::npos)
          << "scene: " << scene << "got: " << message << "\nexpected: " << expected;
      ++checked;
    }
  }
  EXPECT_GE(checked, 15u);
  // Sampled values too: an interval reaching outside is caught where it is drawn.
  EXPECT_NE(PlanErrorOf("LSCENE = ONE(L)\nL = light{elevation:[91,95]}\n")
                .find("s.lscene:2:21: elevation must be within [-90, 90] degrees, sampled 9"),
            std::string::npos);
  EXPECT_NE(PlanErrorOf("LSCENE = ONE(W)\nW = terrain{size:[0,10]}\n")
                .find("s.lscene:2:18: size must be > 0 m"),
            std::string::npos);
  // And inside the range the same keys are fine.
  EXPECT_EQ(PlanErrorOf("LSCENE = ONE(L) ONE(G)\nL = light{elevation:90}\nG = "
                        "georeference{latitude:-90,longitude:180}\n"),
            "");
}

// The frames of a capture over a small scene, without the source texts.
std::string FramesOf(const std::string& capture) {
  const SourceFile scene = ParseSource(
      "LSCENE = ONE(W) ONE(T)\nW = terrain{size:[40,40]}\nT = object{class:cube,position:{ON:W}}\n",
      "s.lscene",
      false);
  const SourceFile cap = ParseSource(capture, "c.lcap", false);
  return PlanToJson(MakePlanFromSources(scene, &cap, 3))["frames"].dump();
}

TEST(Vocabulary, LcapAliasesAndRangesComeFromTheTable) {
  // create point: `attitude` is `rotation`; create hemi: `target` is `center`.
  EXPECT_EQ(FramesOf("LCAP = ONE(P)\nP = path{point:{position:[0,0,20],rotation:[0,-60,30]}}\n"),
            FramesOf("LCAP = ONE(P)\nP = path{point:{position:[0,0,20],Attitude:[0,-60,30]}}\n"));
  EXPECT_EQ(FramesOf("LCAP = ONE(P)\nP = path{hemi:{cam_radius:10,obj_angle:[0,360,4],cam_angle:"
                     "45,center:[1,2,0]}}\n"),
            FramesOf("LCAP = ONE(P)\nP = path{hemi:{cam_radius:10,obj_angle:[0,360,4],cam_angle:"
                     "45,target:[1,2,0]}}\n"));
  const std::string scene =
      "LSCENE = ONE(W) ONE(T)\nW = terrain{size:[40,40]}\nT = object{class:cube,position:{ON:W}}\n";
  const std::string random = "P = path{random:{count:2,off_nadir:";
  EXPECT_NE(PlanErrorOf(scene, "LCAP = ONE(P)\n" + random + "95}}\n")
                .find("c.lcap:2:" + std::to_string(random.size() + 1) +
                      ": off_nadir must be within [0, 90] degrees, found 95"),
            std::string::npos)
      << PlanErrorOf(scene, "LCAP = ONE(P)\n" + random + "95}}\n");
  const std::string flight = "P = path{waypoints:{points:[[0,0,40],[30,0,40]],speed:";
  EXPECT_NE(PlanErrorOf(scene, "LCAP = ONE(P)\n" + flight + "0}}\n")
                .find("c.lcap:2:" + std::to_string(flight.size() + 1) +
                      ": speed must be within (0, 1000] m/s"),
            std::string::npos)
      << PlanErrorOf(scene, "LCAP = ONE(P)\n" + flight + "0}}\n");
  EXPECT_NE(PlanErrorOf(scene, "LCAP = ONE(C)\nC = camera{csettings:{fps:0}}\n")
                .find("c.lcap:2:27: fps must be > 0, found 0"),
            std::string::npos)
      << PlanErrorOf(scene, "LCAP = ONE(C)\nC = camera{csettings:{fps:0}}\n");
}

TEST(Vocabulary, RangeTextAndMembership) {
  const Range r{-90, 90, false, false, ""};
  EXPECT_TRUE(r.Contains(-90));
  EXPECT_TRUE(r.Contains(90));
  EXPECT_FALSE(r.Contains(90.5));
  EXPECT_FALSE(r.Contains(std::nan("")));
  EXPECT_EQ(r.Text(), "within [-90, 90]");
  const Range open{0, std::numeric_limits<double>::infinity(), true, false, ""};
  EXPECT_FALSE(open.Contains(0));
  EXPECT_EQ(open.Text(), "> 0");
  const Range whole{0, 10, false, true, ""};
  EXPECT_FALSE(whole.Contains(2.5));
  EXPECT_EQ(whole.Text(), "a whole number within [0, 10]");
}

TEST(Vocabulary, DocsTablesAreTheGeneratedOnes) {
  const std::string path = kRoot + "/docs/languages.md";
  const std::string doc = ReadFile(path);
  EXPECT_EQ(UpdateVocabularyDocs(doc, path), doc)
      << "docs/languages.md's vocabulary tables differ from generator/lang/vocabulary.cc; "
      << kRegenerate;
  // The golden notices a changed entry: a key's doc line edited by hand.
  std::string edited = doc;
  const size_t at = edited.find("deg above horizon");
  ASSERT_NE(at, std::string::npos);
  edited.replace(at, 17, "degrees up");
  ASSERT_NE(edited, doc);
  EXPECT_NE(UpdateVocabularyDocs(edited, path), edited);
  // Every table is there, with every LSCENE kind and object key.
  for (const KindSpec& kind : Vocabulary()) {
    if (!kind.language.empty()) {
      EXPECT_NE(doc.find("| `" + kind.id + "`"), std::string::npos) << kind.id;
    }
  }
  for (const KeySpec& key : KindVocabulary("object").keys)
    EXPECT_NE(doc.find("| `" + key.name + "`"), std::string::npos) << key.name;
  EXPECT_THROW(UpdateVocabularyDocs("# no markers\n", "x.md"), Error);
}

TEST(Vocabulary, SchemasListTheTableKeys) {
  for (const auto& [file, language] :
       {std::pair<std::string, std::string>{"lscene.schema.json", "LSCENE"},
        std::pair<std::string, std::string>{"lcap.schema.json", "LCAP"}}) {
    const std::string text = ReadFile(kRoot + "/schemas/" + file);
    EXPECT_EQ(UpdateVocabularySchema(text, language), text)
        << "schemas/" << file << " differs from generator/lang/vocabulary.cc; " << kRegenerate;
    const nlohmann::json schema = nlohmann::json::parse(text);
    const nlohmann::json& kinds = schema["definitions"]["kinds"]["properties"];
    // Every kind of the language and every spelling of its keys is in the schema...
    for (const KindSpec& kind : Vocabulary()) {
      if (kind.language != language) continue;
      ASSERT_TRUE(kinds.contains(kind.id)) << file << ": " << kind.id;
      for (const std::string& s : kind.Spellings())
        EXPECT_TRUE(kinds[kind.id]["properties"].contains(s))
            << file << ": " << kind.id << "." << s;
    }
    // ... and every schema key is a spelling of the table, with the table's value type.
    for (const auto& [id, kind_schema] : kinds.items()) {
      const KindSpec& kind = KindVocabulary(id);
      if (!kind_schema.contains("properties")) continue;
      for (const auto& [key, key_schema] : kind_schema["properties"].items()) {
        const KeySpec* spec = kind.Find(CanonicalKey(key));
        ASSERT_NE(spec, nullptr) << file << ": " << id << "." << key;
        if (key == spec->name) {
          EXPECT_EQ(key_schema["$comment"].get<std::string>().rfind(ValueTypeName(spec->type), 0),
                    0u)
              << file << ": " << id << "." << key;
        }
      }
    }
    // The golden notices a changed key.
    std::string edited = text;
    const std::string needle = language == "LSCENE" ? "\"elevation\"" : "\"ev100\"";
    edited.replace(edited.find(needle), needle.size(), "\"elevashun\"");
    EXPECT_NE(UpdateVocabularySchema(edited, language), edited);
  }
}

TEST(Vocabulary, CheckModeOfThePrinterPassesOnTheRepository) {
  const std::string printer = ::lsds::testing::BinaryDir() + "/tests/generator/vocabulary_print";
  EXPECT_EQ(std::system((printer + " --check " + kRoot).c_str()), 0) << kRegenerate;
}

}  // namespace
}  // namespace lsds
