#include "python/json_to_python.h"

namespace lsds::python {

namespace py = pybind11;

py::object ToPython(const nlohmann::json& value) {
  using Type = nlohmann::json::value_t;
  switch (value.type()) {
    case Type::boolean:
      return py::bool_(value.get<bool>());
    case Type::number_integer:
      return py::int_(value.get<int64_t>());
    case Type::number_unsigned:
      return py::int_(value.get<uint64_t>());
    case Type::number_float:
      return py::float_(value.get<double>());
    case Type::string:
      return py::str(value.get_ref<const std::string&>());
    case Type::array: {
      py::list list(value.size());
      for (size_t i = 0; i < value.size(); ++i) list[i] = ToPython(value[i]);
      return std::move(list);
    }
    case Type::object: {
      py::dict dict;
      for (const auto& [key, member] : value.items()) dict[py::str(key)] = ToPython(member);
      return std::move(dict);
    }
    default:  // null; binary and discarded values do not come out of a parsed file
      return py::none();
  }
}

}  // namespace lsds::python
