// The page's inline CSS and JavaScript (plain, no library): class filter on
// the contact sheet, a frame's objects and layers on click, an error hook that
// marks the page when any script fails (tests read it).
#pragma once

namespace lsds::report {

const char* PageStyle();
const char* PageScript();

}  // namespace lsds::report
