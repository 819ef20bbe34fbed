// nlohmann-json's parse failures turned into located lsds::Error: syntax
// errors and malformed UTF-8 at line:column with an excerpt of the text there,
// numbers beyond the range of double (`1e999`, which nlohmann reports with no
// position) at the line:column of the number.
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "libs/util/error.h"

namespace lsds {

// `text` is the document (or the part of it that was parsed); `first_line` is
// the line of the file where `text` starts (for a part of a file).
Error JsonParseError(std::string_view text,
                     const std::string& file,
                     const nlohmann::json::exception& e,
                     int first_line = 1);

// `value` as an integer of type T, range-checked: nlohmann converts silently
// (2^32+1 becomes 1 as int, -1 becomes 4294967295 as uint32, 2.5 becomes 2).
// Throws nlohmann's out_of_range naming `what` and the value (or its
// type_error for a non-number), which the readers turn into an error at the
// JSON pointer.
template <typename T>
T JsonInteger(const nlohmann::json& value, const std::string& what) {
  static_assert(std::is_integral_v<T>);
  if (!value.is_number()) return value.get<T>();  // nlohmann's type_error
  constexpr T lo = std::numeric_limits<T>::min();
  constexpr T hi = std::numeric_limits<T>::max();
  bool ok = false;
  if (value.is_number_unsigned()) {
    ok = value.get<uint64_t>() <= static_cast<uint64_t>(hi);
  } else if (value.is_number_integer()) {
    const int64_t v = value.get<int64_t>();
    ok = v >= static_cast<int64_t>(lo) &&
         (v < 0 || static_cast<uint64_t>(v) <= static_cast<uint64_t>(hi));
  } else {
    const double v = value.get<double>();
    // hi + 1 = 2^digits exactly: the double of hi itself may round up past it.
    ok = std::isfinite(v) && v == std::floor(v) && v >= static_cast<double>(lo) &&
         v < std::ldexp(1.0, std::numeric_limits<T>::digits);
  }
  if (!ok) {
    throw nlohmann::json::out_of_range::create(406,
                                               what + ": " + value.dump() +
                                                   " is not an integer in [" + std::to_string(lo) +
                                                   ", " + std::to_string(hi) + "]",
                                               nullptr);
  }
  return value.get<T>();
}

// The integer member `key` of `object`, range-checked (JsonInteger).
template <typename T>
T GetInteger(const nlohmann::json& object, const char* key) {
  return JsonInteger<T>(object.at(key), key);
}

// Runs `body`, turning nlohmann's type and range errors (a string where a
// number belongs, GetInteger's range check) into lsds::Error at
// `file#pointer`: the readers of JSON inputs report a wrong type where it is,
// never as an internal error.
template <typename Body>
auto AtPointer(const std::string& file, const std::string& pointer, Body&& body)
    -> decltype(body()) {
  try {
    return body();
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("malformed value: ") + e.what(),
                Location(file, pointer.empty() ? "/" : pointer));
  }
}

// Parses a whole document with located errors; a NUL byte anywhere is one
// (nlohmann would take it for the end of the input).
nlohmann::json ParseJsonText(std::string_view text, const std::string& file);

// A whole JSON input file (reports, settings, importers' JSON): read with
// ReadTextFile (the memory budget, a NUL byte refused where it is), nesting
// bounded (CheckJsonNesting), parsed with located errors.
nlohmann::json ReadJsonFile(const std::filesystem::path& path);

}  // namespace lsds
