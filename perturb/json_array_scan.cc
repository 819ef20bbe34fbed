#include "perturb/json_array_scan.h"

#include <cstring>
#include <fstream>
#include <vector>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "libs/util/limits.h"
#include "libs/util/text_check.h"

namespace lsds::noise {

namespace {

bool IsSpace(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

std::string_view TrimRight(std::string_view text) {
  while (!text.empty() && IsSpace(text.back())) text.remove_suffix(1);
  return text;
}

}  // namespace

// One byte-level scanner loop (a parser state machine).
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
ArrayScanResult ScanJsonArrayMember(const std::filesystem::path& path,
                                    const std::string& array_key,
                                    const ArrayScanCallbacks& callbacks) {
  RequireRegularFile(path, "JSON file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open for reading", Location(path.string()));

  ArrayScanResult result;
  std::string header_text;  // everything but the array's contents
  std::string element;      // the element being read
  std::string key;          // the last key string at depth 1
  int depth = 0;
  bool in_string = false, escape = false;
  bool key_string = false;    // the current string is a key at depth 1
  bool expect_key = false;    // at depth 1, after '{' or ','
  bool value_of_key = false;  // at depth 1, after "key":
  bool in_array = false;      // inside the target array
  bool array_done = false;
  bool in_element = false;
  size_t element_start = 0;  // where the current element starts in this chunk
  const bool want_elements = static_cast<bool>(callbacks.on_element);

  std::vector<char> buffer(1 << 20);
  uint64_t chunk_start = 0;  // the file offset of buffer[0]
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const size_t got = static_cast<size_t>(in.gcount());
    if (got == 0) break;
    // No NUL anywhere: the header and element parses would take one for the
    // end of their text.
    if (const void* nul = std::memchr(buffer.data(), '\0', got)) {
      const uint64_t offset =
          chunk_start + static_cast<uint64_t>(static_cast<const char*>(nul) - buffer.data());
      throw Error(NulByteMessage(offset), TextLocationInFile(path, offset));
    }
    chunk_start += got;
    size_t raw_start = 0;  // the array bytes of this chunk not handed out yet
    for (size_t i = 0; i < got; ++i) {
      const char c = buffer[i];
      if (in_array) {
        // Inside the array: depth >= 2 until its closing ']'. Element bytes are
        // appended in runs (from element_start to the current position) rather
        // than one by one.
        if (in_string) {
          if (escape) {
            escape = false;
          } else if (c == '\\') {
            escape = true;
          } else if (c == '"') {
            in_string = false;
          }
          continue;
        }
        if (depth == 2 && (c == ',' || c == ']')) {
          if (in_element) {
            if (want_elements) {
              element.append(buffer.data() + element_start, i - element_start);
              callbacks.on_element(TrimRight(element), result.elements);
              element.clear();
            }
            ++result.elements;
            in_element = false;
          }
          if (c == ']') {
            if (callbacks.on_raw) {
              callbacks.on_raw(std::string_view(buffer.data() + raw_start, i - raw_start));
            }
            in_array = false;
            array_done = true;
            depth = 1;
            header_text += c;
          }
          continue;
        }
        if (!in_element) {
          if (IsSpace(c)) continue;
          in_element = true;
          element_start = i;
        }
        if (c == '"') {
          in_string = true;
        } else if (c == '{' || c == '[') {
          ++depth;
        } else if (c == '}' || c == ']') {
          --depth;
        }
        continue;
      }
      header_text += c;
      if (in_string) {
        if (escape) {
          escape = false;
        } else if (c == '\\') {
          escape = true;
        } else if (c == '"') {
          in_string = false;
          if (key_string) {
            key_string = false;
            expect_key = false;
          }
        } else if (key_string) {
          key += c;
        }
        continue;
      }
      if (IsSpace(c)) continue;
      if (c == '"') {
        in_string = true;
        if (depth == 1 && expect_key) {
          key_string = true;
          key.clear();
        }
        value_of_key = false;
        continue;
      }
      if (depth == 1 && c == ':') {
        value_of_key = true;
        continue;
      }
      if (c == '[' && depth == 1 && value_of_key && key == array_key && !array_done) {
        in_array = true;
        result.found = true;
        depth = 2;
        raw_start = i + 1;
        value_of_key = false;
        continue;
      }
      value_of_key = false;
      if (c == '{' || c == '[') {
        ++depth;
        expect_key = depth == 1 && c == '{';
      } else if (c == '}' || c == ']') {
        --depth;
      } else if (c == ',' && depth == 1) {
        expect_key = true;
      }
    }
    if (in_array && callbacks.on_raw) {
      callbacks.on_raw(std::string_view(buffer.data() + raw_start, got - raw_start));
    }
    // An element cut by the end of the chunk: keep its first part.
    if (in_element && want_elements) {
      element.append(buffer.data() + element_start, got - element_start);
    }
    element_start = 0;
  }
  if (in.bad()) throw Error("read error", Location(path.string()));
  // The place is the end of the file, where the closing ']' was expected.
  if (in_array)
    throw Error("invalid JSON: the \"" + array_key + "\" array is not closed",
                TextLocationInFile(path, chunk_start));
  if (FindExcessJsonNesting(header_text) != std::string_view::npos)
    throw Error(NestingMessage(), Location(path.string()));
  // Lines and columns are exact up to the array (the header text lacks its
  // contents).
  result.header = ParseJsonText(header_text, path.string());
  if (!result.header.is_object()) {
    throw Error("top level must be a JSON object", Location(path.string(), "/"));
  }
  return result;
}

nlohmann::json ParseElement(std::string_view text,
                            const std::filesystem::path& path,
                            const std::string& pointer) {
  if (FindExcessJsonNesting(text) != std::string_view::npos)
    throw Error(NestingMessage(), Location(path.string(), pointer));
  try {
    return nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {
    if (e.id < 101 || (e.id > 199 && e.id != 406)) throw;
    // The error path only: find the element in the file for its line and
    // column (element texts are the file's exact bytes).
    std::string file_text;
    try {
      file_text = ReadFile(path);
    } catch (const Error&) {
    }
    const size_t at = file_text.find(text);
    Error located = JsonParseError(text, path.string(), e);
    Location where = located.location();
    where.json_pointer = pointer;
    if (at != std::string::npos && where.line > 0) {
      int line = 0, column = 0;
      LineColumnFromOffset(file_text, at, &line, &column);
      where.column = where.line == 1 ? where.column + column - 1 : where.column;
      where.line += line - 1;
    }
    throw Error(located.message(), where);
  }
}

std::string ArrayFileHead(const nlohmann::json& header, const std::string& array_key) {
  nlohmann::json members = header;
  members.erase(array_key);
  std::string text = members.dump(2);
  text.erase(text.find_last_of('}'));
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text + (members.empty() ? "\n" : ",\n") + "  " + nlohmann::json(array_key).dump() + ": [";
}

}  // namespace lsds::noise
