// Reading a source's JSON files with located errors: every importer names the
// file and the JSON pointer of a field that is missing or malformed.
#pragma once

#include <filesystem>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"

namespace lsds::import {

inline nlohmann::json ParseJsonFile(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error("missing file", Location(path.string()));
  return ReadJsonFile(path);
}

// Runs `body`, turning a JSON access error into one located at file#pointer.
template <typename F>
auto AtField(const std::string& file, const std::string& pointer, F&& body) {
  try {
    return body();
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("malformed field: ") + e.what(), Location(file, pointer));
  }
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
