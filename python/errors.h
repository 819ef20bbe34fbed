// lsds's errors as Python exceptions (docs/python.md, "Exceptions"): lsds.Error and its kinds,
// carrying the located message the CLI prints, and lsds.Location.
#pragma once

#include <pybind11/pybind11.h>

#include "libs/util/error.h"

namespace lsds::python {

// Adds Location, Error, UsageError, DataError and InternalError to `module` and translates
// python::UsageError (python/usage_error.h: the caller's arguments) to UsageError, every other
// lsds::Error and std::filesystem::filesystem_error (the input) to DataError, and
// lsds::InternalError to InternalError.
void RegisterErrors(pybind11::module_& module);

}  // namespace lsds::python
