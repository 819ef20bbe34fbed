#include "report/html_text.h"

#include "libs/util/strings.h"

namespace lsds::report {

// One escaping for the page and the XML exports (libs/util/strings.h): the
// five characters that can end a text node or a quoted attribute value.
std::string HtmlEscape(std::string_view text) { return XmlEscape(std::string(text)); }

}  // namespace lsds::report
