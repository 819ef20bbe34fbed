// The parts of the compiled module lsds._lsds (python/module.cc registers them in this order).
#pragma once

#include <pybind11/pybind11.h>

namespace lsds::python {

// lsds.open, Collection, Frame, Camera, Bundle (collection_bindings.cc).
void RegisterCollection(pybind11::module_& module);
// lsds.validate, Report, Finding (validate_bindings.cc).
void RegisterValidate(pybind11::module_& module);

}  // namespace lsds::python
