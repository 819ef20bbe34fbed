#include "libs/util/check.h"

namespace lsds {

void FailCheck(const char* condition, const char* file, int line, const std::string& detail) {
  std::string message = std::string("internal check failed: ") + condition + " (" + file + ":" +
                        std::to_string(line) + ")";
  if (!detail.empty()) message += ": " + detail;
  throw InternalError(message);
}

std::string InternalErrorAdvice() {
  return "this is a bug in lsds " LSDS_VERSION
         ", not a problem with your data; please report it with the command "
         "line and this message";
}

}  // namespace lsds
