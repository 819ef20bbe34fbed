// The errors of a Python caller's arguments: lsds.UsageError, where every other lsds::Error is
// lsds.DataError (python/errors.h).
#pragma once

#include "libs/util/error.h"

namespace lsds::python {

class UsageError : public Error {
 public:
  using Error::Error;
};

// Runs `parse` (a parser of an argument: a --checks list, a --frames range) and reports what it
// throws as a UsageError, with the same message and location.
template <typename Parse>
auto ParseArgument(Parse&& parse) {
  try {
    return parse();
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError(e.message(), e.location());
  }
}

}  // namespace lsds::python
