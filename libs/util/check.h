// Internal invariants: a failed LSDS_CHECK is a bug in lsds, not bad input. It
// throws InternalError, which every command reports with the place in the
// source and a request for a bug report, exit code 70 (kExitInternal), so that
// scripts can tell "my data is bad" (2, 1) from "lsds is broken" (70).
#pragma once

#include <stdexcept>
#include <string>

namespace lsds {

class InternalError : public std::logic_error {
 public:
  explicit InternalError(const std::string& message) : std::logic_error(message) {}
};

[[noreturn]] void FailCheck(const char* condition,
                            const char* file,
                            int line,
                            const std::string& detail);

// The text every command prints for an internal error (the bug-report line).
std::string InternalErrorAdvice();

}  // namespace lsds

// LSDS_CHECK(cond) << nothing: a plain macro; LSDS_CHECK_MSG adds context.
#define LSDS_CHECK(condition)                                                           \
  do {                                                                                  \
    if (!(condition)) ::lsds::FailCheck(#condition, __FILE__, __LINE__, std::string()); \
  } while (false)

#define LSDS_CHECK_MSG(condition, detail)                                          \
  do {                                                                             \
    if (!(condition)) ::lsds::FailCheck(#condition, __FILE__, __LINE__, (detail)); \
  } while (false)
