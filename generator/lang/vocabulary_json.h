// The vocabulary table as data, for programs that write LSCENE/LCAP (`lsds
// language --json`, docs/languages.md "Reflection"): every kind with its
// spellings, and every key with its spellings, value type, unit and range.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace lsds {

// {"format": "lsds-language", "format_version": 1, "value_types": [...],
//  "kinds": [{"id", "language", "aliases", "category", "what", "paper",
//             "keys_listed", "keys": [{"name", "aliases", "type", "unit",
//             "range", "block", "role", "in_change", "doc"}]}]}
// in the table's order; empty fields are left out.
nlohmann::ordered_json VocabularyJson();

// The same, one line per kind and one per key, for people.
std::string VocabularyText();

}  // namespace lsds
