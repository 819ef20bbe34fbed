#include "python/errors.h"

#include <exception>
#include <filesystem>
#include <string>

#include "libs/util/check.h"
#include "python/usage_error.h"

namespace lsds::python {

namespace py = pybind11;

namespace {

struct ErrorTypes {
  py::object usage, data, internal;
};

// Created once at import; never destroyed (the interpreter owns the classes).
ErrorTypes& Types() {
  static auto* types = new ErrorTypes;
  return *types;
}

py::object NewErrorType(py::module_& module, const char* name, const char* doc, py::handle bases) {
  const std::string qualified = std::string("lsds.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (type == nullptr) throw py::error_already_set();
  py::object object = py::reinterpret_steal<py::object>(type);
  module.attr(name) = object;
  return object;
}

// Sets the Python error: an instance of `type` with str() = `what` (the CLI's located message)
// and the attributes message, location and exit_code.
void Raise(const py::object& type,
           const std::string& what,
           const std::string& message,
           const Location& location,
           int exit_code) {
  py::object error = type(what);
  error.attr("message") = message;
  error.attr("location") = py::cast(location);
  error.attr("exit_code") = exit_code;
  PyErr_SetObject(type.ptr(), error.ptr());
}

py::object OrNone(bool set, py::object value) { return set ? std::move(value) : py::none(); }

void RegisterLocation(py::module_& module) {
  py::class_<Location>(module,
                       "Location",
                       "Where in an input something is: only the fields that apply are set "
                       "(the others are None).")
      .def_property_readonly(
          "file", [](const Location& l) { return OrNone(!l.file.empty(), py::str(l.file)); })
      .def_property_readonly("line",
                             [](const Location& l) { return OrNone(l.line > 0, py::int_(l.line)); })
      .def_property_readonly(
          "column", [](const Location& l) { return OrNone(l.column > 0, py::int_(l.column)); })
      .def_property_readonly("json_pointer",
                             [](const Location& l) {
                               return OrNone(!l.json_pointer.empty(), py::str(l.json_pointer));
                             })
      .def_property_readonly("frame",
                             [](const Location& l) {
                               return OrNone(l.frame.has_value(), py::int_(l.frame.value_or(0)));
                             })
      .def_property_readonly(
          "pixel",
          [](const Location& l) {
            const bool set = l.pixel_x && l.pixel_y;
            return OrNone(set, py::make_tuple(l.pixel_x.value_or(0), l.pixel_y.value_or(0)));
          })
      .def("__str__", &Location::ToString)
      .def("__repr__", [](const Location& l) { return "<lsds.Location " + l.ToString() + ">"; });
}

}  // namespace

void RegisterErrors(py::module_& module) {
  RegisterLocation(module);
  const py::object base = NewErrorType(
      module,
      "Error",
      "An lsds error: str() is the located message the CLI prints; .message, .location "
      "(lsds.Location) and .exit_code (the CLI's exit code) say the same in parts.",
      PyExc_Exception);
  ErrorTypes& types = Types();
  types.usage = NewErrorType(module,
                             "UsageError",
                             "Bad usage: an argument lsds cannot take (CLI exit code 2).",
                             py::make_tuple(base, py::handle(PyExc_ValueError)));
  types.data = NewErrorType(module,
                            "DataError",
                            "Unreadable input: a file that is missing, malformed or inconsistent, "
                            "named by .location (CLI exit code 2).",
                            base);
  types.internal = NewErrorType(
      module, "InternalError", "A bug in lsds (CLI exit code 70): please report it.", base);
  // NOLINTNEXTLINE(performance-unnecessary-value-param): pybind11's translator type takes it so
  py::register_exception_translator([](std::exception_ptr error) {
    if (!error) return;
    const ErrorTypes& t = Types();
    try {
      std::rethrow_exception(error);
    } catch (const UsageError& e) {
      Raise(t.usage, e.what(), e.message(), e.location(), kExitUsage);
    } catch (const Error& e) {
      Raise(t.data, e.what(), e.message(), e.location(), kExitUsage);
    } catch (const std::filesystem::filesystem_error& e) {
      // The operating system refused a path (permissions, a vanished file): the message names it.
      Raise(t.data, e.what(), e.what(), Location(e.path1().string()), kExitUsage);
    } catch (const InternalError& e) {
      const std::string what = std::string(e.what()) + "; " + InternalErrorAdvice();
      Raise(t.internal, what, e.what(), Location(), kExitInternal);
    }
  });
}

}  // namespace lsds::python
