// JSON values (nlohmann) as Python objects: what json.load would give for the same text.
#pragma once

#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

namespace lsds::python {

// null -> None, booleans, integers -> int, floating-point numbers -> float, strings, arrays ->
// list, objects -> dict (keys sorted, as nlohmann stores them).
pybind11::object ToPython(const nlohmann::json& value);

}  // namespace lsds::python
