// The compiled part of the Python package lsds (python/lsds/__init__.py re-exports it): thin
// bindings over the collection reader, the layer codecs and the validators (docs/python.md).
// Importing it starts no thread and opens no file.
#include <string>
#include <vector>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "libs/util/plugin.h"
#include "python/bindings.h"
#include "python/errors.h"

namespace py = pybind11;

PYBIND11_MODULE(_lsds, module) {
  module.doc() = "lsds: simulated datasets (collections of EXR layers and JSON truth)";
  module.attr("__version__") = LSDS_VERSION;
  lsds::python::RegisterErrors(module);
  lsds::python::RegisterCollection(module);
  lsds::python::RegisterValidate(module);
  module.def("plugin_search_dirs",
             &lsds::PluginSearchDirs,
             "The folders searched for lsds's plug-ins, in order (docs/architecture.md, "
             "\"Plug-ins\").");
}
