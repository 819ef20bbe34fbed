// What a validator check reports: typed findings with a severity, a check id
// and a location.
#pragma once

#include <string>

#include "libs/util/error.h"

namespace lsds::validate {

enum class Severity { kInfo = 0, kWarning = 1, kError = 2 };
const char* SeverityName(Severity severity);  // "info" | "warning" | "error"
bool ParseSeverity(const std::string& name, Severity* severity);

struct Finding {
  Severity severity = Severity::kError;
  std::string check_id;  // an id of the registry (checks.h), e.g. "layer.depth-finite"
  Location location;     // file, frame, pixel or JSON pointer; only the fields
                         // that apply
  std::string object;    // "instance 3 (box)" when the finding is about one object
  std::string message;
};

}  // namespace lsds::validate
