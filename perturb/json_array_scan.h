// One fast streaming pass over a JSON file whose root object holds one large
// array member (collection.json's and metadata.json's "frames"), without
// building a DOM for the whole file: the bytes of the array are handed out
// verbatim (so a file can be rewritten with its frames byte-identical) and each
// element's text is handed out for parsing on its own. nlohmann's SAX callback
// parser is several times slower than this scan plus a parse per element.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace lsds::noise {

struct ArrayScanCallbacks {
  // The exact bytes between the array's '[' and its ']' (in pieces, in order).
  std::function<void(std::string_view bytes)> on_raw;
  // The text of each element, without surrounding whitespace or commas.
  std::function<void(std::string_view text, size_t index)> on_element;
};

struct ArrayScanResult {
  nlohmann::json header;  // the root object with `array_key` set to []; parsed
  bool found = false;     // the root object has `array_key` and it is an array
  size_t elements = 0;
};

// Throws lsds::Error naming the file on unreadable input, invalid JSON around
// the array, or a root that is not an object. Elements are not checked here:
// parse their text (ParseElement).
ArrayScanResult ScanJsonArrayMember(const std::filesystem::path& path,
                                    const std::string& array_key,
                                    const ArrayScanCallbacks& callbacks = {});

// Parses an element's text; throws lsds::Error naming the file and the pointer
// "/KEY/INDEX".
nlohmann::json ParseElement(std::string_view text,
                            const std::filesystem::path& path,
                            const std::string& pointer);

// The text that JsonArrayWriter writes before the elements: the header members
// (pretty, without `array_key`), then `"array_key": [`.
std::string ArrayFileHead(const nlohmann::json& header, const std::string& array_key);

}  // namespace lsds::noise
