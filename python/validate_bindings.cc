// lsds.validate, lsds.Report and lsds.Finding (docs/python.md, "Validation"): `lsds validate` as a
// function, over the same library.
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "libs/collection/frame_selection_check.h"
#include "libs/util/frame_selection.h"
#include "python/bindings.h"
#include "python/json_to_python.h"
#include "python/usage_error.h"
#include "validators/report_writers.h"
#include "validators/validate.h"

namespace lsds::python {

namespace py = pybind11;

namespace {

using validate::Finding;
using validate::Severity;

struct PyReport {
  validate::Report report;
  Severity fail_on = Severity::kError;

  std::vector<Finding> Findings() const {
    std::vector<Finding> findings;
    for (const std::string& id : report.checks) {
      const auto it = report.results().find(id);
      if (it == report.results().end()) continue;
      findings.insert(findings.end(), it->second.examples.begin(), it->second.examples.end());
    }
    return findings;
  }
  py::dict Counts() const {
    py::dict counts;
    for (Severity s : {Severity::kError, Severity::kWarning, Severity::kInfo})
      counts[validate::SeverityName(s)] = report.Count(s);
    return counts;
  }
};

Severity ParseFailOn(const std::string& name) {
  Severity severity = Severity::kError;
  if (!validate::ParseSeverity(name, &severity))
    throw UsageError("fail_on: expected error, warning or info, got '" + name + "'");
  return severity;
}

// The text of `frames` in the one --frames grammar (libs/util/frame_selection.h): a
// string as the flag takes it ("A:B", "A:", ":B", "N"), an int N, or a Python slice
// a:b (no step), so that the CLI's parser checks every form.
std::string FramesText(const py::object& frames) {
  if (frames.is_none()) return "";
  if (py::isinstance<py::str>(frames)) return frames.cast<std::string>();
  if (py::isinstance<py::int_>(frames) && !py::isinstance<py::bool_>(frames))
    return std::to_string(frames.cast<int64_t>());
  if (py::isinstance<py::slice>(frames)) {
    const py::object start = frames.attr("start"), stop = frames.attr("stop"),
                     step = frames.attr("step");
    if (!step.is_none() && step.cast<int64_t>() != 1)
      throw UsageError("frames: a slice with a step is no --frames range, got step " +
                       py::str(step).cast<std::string>());
    const auto bound = [](const py::object& value) {
      return value.is_none() ? std::string() : std::to_string(value.cast<int64_t>());
    };
    return bound(start) + ":" + bound(stop);
  }
  throw UsageError(
      "frames: expected a --frames range ('A:B', 'A:', ':B', 'N'), an int or a "
      "slice, got " +
      py::str(frames.get_type().attr("__name__")).cast<std::string>());
}

PyReport Validate(const std::filesystem::path& path,
                  const std::string& checks,
                  const py::object& frames_argument,
                  int jobs,
                  size_t max_examples,
                  const std::string& fail_on) {
  if (max_examples < 1) throw UsageError("max_examples must be at least 1");
  if (jobs < 0)
    throw UsageError("jobs must be 0 (every core) or more, got " + std::to_string(jobs));
  validate::ValidateOptions options;
  options.checks = ParseArgument([&] { return validate::CheckSelection::Parse(checks); });
  const std::string frames = FramesText(frames_argument);
  // As the CLI: the range parsed and checked against the collection's frames (an unreadable
  // collection is the DataError below, from the validation itself).
  if (!frames.empty()) {
    const FrameSelection selection =
        ParseArgument([&] { return ParseFrameSelection(frames, "frames"); });
    const std::vector<int64_t> indices = CollectionFrameIndices(path);  // DataError if unreadable
    ParseArgument([&] {
      CheckFrameSelection(selection, indices, "the collection " + path.string());
      return 0;
    });
    options.frames = selection;
  }
  options.jobs = jobs;
  options.max_examples = max_examples;
  PyReport out{validate::Report(max_examples), ParseFailOn(fail_on)};
  py::gil_scoped_release release;
  out.report = validate::ValidateCollection(path, options);
  return out;
}

std::string FindingText(const Finding& f) {
  const std::string where = f.location.ToString();
  std::string text = std::string(validate::SeverityName(f.severity)) + " " + f.check_id + ": ";
  if (!where.empty()) text += where + ": ";
  if (!f.object.empty()) text += f.object + ": ";
  return text + f.message;
}

void RegisterFinding(py::module_& m) {
  py::class_<Finding>(m, "Finding", "One finding of lsds.validate.")
      .def_property_readonly(
          "severity",
          [](const Finding& f) { return validate::SeverityName(f.severity); },
          "'error', 'warning' or 'info'")
      .def_readonly("code",
                    &Finding::check_id,
                    "the check's id, e.g. 'layer.depth-finite' (docs/validate.md)")
      .def_readonly("message", &Finding::message)
      .def_readonly("location", &Finding::location, "an lsds.Location")
      .def_property_readonly(
          "object",
          [](const Finding& f) -> py::object {
            if (f.object.empty()) return py::none();
            return py::str(f.object);
          },
          "the object the finding is about ('instance 3 (box)'), or None")
      .def(
          "as_dict",
          [](const Finding& f) { return ToPython(validate::FindingToJson(f)); },
          "the finding as the JSON report writes it")
      .def("__str__", &FindingText)
      .def("__repr__", [](const Finding& f) { return "<lsds.Finding " + FindingText(f) + ">"; });
}

void RegisterReport(py::module_& m) {
  py::class_<PyReport>(m, "Report", "The outcome of lsds.validate.")
      .def_property_readonly("findings",
                             &PyReport::Findings,
                             "the findings kept (up to max_examples per check, earliest frames "
                             "first), checks in registry order")
      .def_property_readonly(
          "counts",
          &PyReport::Counts,
          "every finding counted by severity: {'error': n, 'warning': n, 'info': n}")
      .def(
          "count",
          [](const PyReport& r, const std::string& code) { return r.report.CountOf(code); },
          py::arg("code"),
          "the number of findings of one check")
      .def_property_readonly(
          "ok",
          [](const PyReport& r) { return !r.report.Fails(r.fail_on); },
          "no finding at or above fail_on")
      .def_property_readonly(
          "exit_code",
          [](const PyReport& r) { return r.report.Fails(r.fail_on) ? 1 : 0; },
          "what `lsds validate --fail-on` would exit with: 0 or 1")
      .def_property_readonly("checks", [](const PyReport& r) { return r.report.checks; })
      .def_property_readonly(
          "frames", [](const PyReport& r) { return r.report.frames; }, "frames checked")
      .def(
          "text",
          [](const PyReport& r) { return validate::ReportToText(r.report, r.fail_on); },
          "the report as `lsds validate` prints it")
      .def(
          "json",
          [](const PyReport& r) { return ToPython(validate::ReportToJson(r.report, r.fail_on)); },
          "the report of `lsds validate --format json`, as a dict")
      .def(
          "junit",
          [](const PyReport& r) { return validate::ReportToJUnit(r.report, r.fail_on); },
          "the report of `lsds validate --format junit`")
      .def("__repr__", [](const PyReport& r) {
        return "<lsds.Report " + validate::Verdict(r.report, r.fail_on) + ">";
      });
}

}  // namespace

void RegisterValidate(py::module_& m) {
  RegisterFinding(m);
  RegisterReport(m);
  m.def("validate",
        &Validate,
        py::arg("path"),
        py::kw_only(),
        py::arg("checks") = "all",
        py::arg("frames") = py::none(),
        py::arg("jobs") = 0,
        py::arg("max_examples") = 20,
        py::arg("fail_on") = "error",
        "Checks the collection folder `path` as `lsds validate` does and returns an lsds.Report. "
        "checks: ids or groups as --checks; frames: as --frames ('A:B', 'A:', ':B', 'N'), an int "
        "N or a slice a:b (frame indices, half-open); jobs: worker threads "
        "(0: every core; TBB threads stay alive afterwards); max_examples, fail_on: as the CLI's. "
        "Raises lsds.DataError when `path` cannot be read as a collection at all.");
}

}  // namespace lsds::python
