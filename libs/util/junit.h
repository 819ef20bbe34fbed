// The one JUnit XML writer (validate, merge-reports and check-export): one
// <testsuites> with one <testsuite> of test cases.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lsds {

struct JUnitCase {
  enum class Outcome { kPassed, kOutput, kFailure };
  std::string classname;
  std::string name;
  std::string time;  // as written, e.g. "0.012"
  Outcome outcome = Outcome::kPassed;
  std::string failure_message;  // kFailure: the message attribute
  std::string failure_type;     // kFailure: the type attribute
  std::string body;             // kFailure: the failure text; kOutput: <system-out>
};

struct JUnitSuite {
  std::string suites_name;  // <testsuites name=...>
  std::string name;         // <testsuite name=...>
  std::string time;         // as written
  std::vector<JUnitCase> cases;
};

// The document, every attribute and text escaped.
std::string JUnitXml(const JUnitSuite& suite);

}  // namespace lsds
