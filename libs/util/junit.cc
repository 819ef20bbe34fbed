#include "libs/util/junit.h"

#include <sstream>

#include "libs/util/strings.h"

namespace lsds {

std::string JUnitXml(const JUnitSuite& suite) {
  int64_t failures = 0;
  for (const JUnitCase& c : suite.cases) failures += c.outcome == JUnitCase::Outcome::kFailure;
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << "<testsuites name=\"" << XmlEscape(suite.suites_name) << "\" tests=\""
      << suite.cases.size() << "\" failures=\"" << failures << "\" time=\"" << suite.time
      << "\">\n";
  out << "  <testsuite name=\"" << XmlEscape(suite.name) << "\" tests=\"" << suite.cases.size()
      << "\" failures=\"" << failures << "\" errors=\"0\" time=\"" << suite.time << "\">\n";
  for (const JUnitCase& c : suite.cases) {
    out << "    <testcase classname=\"" << XmlEscape(c.classname) << "\" name=\""
        << XmlEscape(c.name) << "\" time=\"" << c.time << "\">\n";
    if (c.outcome == JUnitCase::Outcome::kFailure) {
      out << "      <failure message=\"" << XmlEscape(c.failure_message) << "\" type=\""
          << XmlEscape(c.failure_type) << "\">" << XmlEscape(c.body) << "</failure>\n";
    } else if (c.outcome == JUnitCase::Outcome::kOutput) {
      out << "      <system-out>" << XmlEscape(c.body) << "</system-out>\n";
    }
    out << "    </testcase>\n";
  }
  out << "  </testsuite>\n</testsuites>\n";
  return out.str();
}

}  // namespace lsds
