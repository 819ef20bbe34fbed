// A number of a prediction text file (YOLO, MOT): Python's float() of one
// field, finite, or an lsds::Error at its place.
#pragma once

#include <cmath>
#include <cstdlib>
#include <string>

#include "libs/util/error.h"

namespace lsds::evaluate {

inline double FiniteNumber(const std::string& token, const Location& at) {
  char* end = nullptr;
  const double value = std::strtod(token.c_str(), &end);
  if (token.empty() || end != token.c_str() + token.size() || !std::isfinite(value))
    throw Error("not a finite number: '" + token + "'", at);
  return value;
}

}  // namespace lsds::evaluate
