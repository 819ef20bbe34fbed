// Prints the vocabulary (vocabulary.h) as the tables of docs/languages.md and
// as the keys part of schemas/lscene.schema.json and lcap.schema.json, so that
// the committed files follow the one table. tests/generator/vocabulary_test.cc
// fails when they differ; tests/generator/vocabulary_print regenerates them.
#pragma once

#include <string>
#include <vector>

namespace lsds {

// The ids of the generated docs tables, in the order they appear.
std::vector<std::string> VocabularyDocTables();
// One table as markdown ("lscene-symbols", "object-keys", "lcap-symbols", "path-generators",
// "camera-settings", "capture-settings"); throws lsds::Error for another id.
std::string VocabularyMarkdown(const std::string& table);
// `doc` (docs/languages.md) with every generated section - the lines between
// "<!-- vocabulary:ID -->" and "<!-- /vocabulary:ID -->" - replaced by the
// current table. Throws lsds::Error naming `path` when a marker is missing.
std::string UpdateVocabularyDocs(const std::string& doc, const std::string& path);

// `schema_text` (lscene.schema.json when `language` is "LSCENE", else
// lcap.schema.json) with its "definitions/kinds" replaced by the vocabulary's
// kinds and keys of that language, printed as the committed file is.
std::string UpdateVocabularySchema(const std::string& schema_text, const std::string& language);

}  // namespace lsds
