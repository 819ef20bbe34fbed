// The page's inline CSS and JavaScript (plain, no library): class filter on
// the contact sheet, a frame's objects and layers on click, an error hook that
// marks the page when any script fails (tests read it).
#pragma once

#include "report/html_text.h"

namespace lsds::report {

Html PageStyle();
Html PageScript();

}  // namespace lsds::report
