// Reading a source's JSON files with located errors: every importer names the
// file and the JSON pointer of a field that is missing or malformed, and reads
// ids, integers and strings through the checked accessors below (never a bare
// get<uint32_t>(), which wraps 2^32 + 2 to 2 and -1 to 4294967295).
#pragma once

#include <filesystem>
#include <limits>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"
#include "libs/util/limits.h"
#include "libs/util/text_check.h"

namespace lsds::import {

// `path` must already be confined (ConfinedFolder::File) or given by the user.
inline nlohmann::json ParseJsonFile(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error("missing file", Location(path.string()));
  return ReadJsonFile(path);
}

// A JSON value for a message: its text, shortened.
inline std::string ValueText(const nlohmann::json& value) { return Excerpt(value.dump(), 60); }

// The integer `value` at file#pointer, in [lo, hi]; a located error naming the
// value otherwise (a string, a fraction, a number out of range).
template <typename T>
T IntegerAt(const nlohmann::json& value,
            const std::string& file,
            const std::string& pointer,
            T lo = std::numeric_limits<T>::min(),
            T hi = std::numeric_limits<T>::max()) {
  T result{};
  bool ok = true;
  try {
    result = JsonInteger<T>(value, pointer);
  } catch (const nlohmann::json::exception&) {
    ok = false;
  }
  if (!ok || result < lo || result > hi)
    throw Error("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                    "], got " + ValueText(value),
                Location(file, pointer));
  return result;
}

// An id (class, instance, label, model): lsds' id layers are 32-bit unsigned,
// so an id outside [0, 2^32) is refused rather than wrapped onto another id.
inline uint32_t IdAt(const nlohmann::json& value,
                     const std::string& file,
                     const std::string& pointer) {
  return IntegerAt<uint32_t>(value, file, pointer);
}

// The string `value` at file#pointer; a located error for any other type.
inline std::string StringAt(const nlohmann::json& value,
                            const std::string& file,
                            const std::string& pointer) {
  if (!value.is_string())
    throw Error("expected a string, got " + ValueText(value), Location(file, pointer));
  return value.get<std::string>();
}

// A fixed-size array of numbers (nested arrays are flattened row by row).
template <int N>
Eigen::Matrix<double, N, 1> JsonNumbers(const nlohmann::json& j) {
  nlohmann::json flat = nlohmann::json::array();
  if (j.is_array())
    for (const nlohmann::json& row : j) {
      if (row.is_array())
        for (const nlohmann::json& v : row) flat.push_back(v);
      else
        flat.push_back(row);
    }
  if (flat.size() != static_cast<size_t>(N))
    throw nlohmann::json::type_error::create(302, "expected " + std::to_string(N) + " numbers", &j);
  Eigen::Matrix<double, N, 1> out;
  for (int k = 0; k < N; ++k) out[k] = flat.at(k).get<double>();
  return out;
}

}  // namespace lsds::import
