// libFuzzer target: the report's page writer for the two JSON inputs it shows
// (`lsds report --validation-report`, `--bundle-stats`). The same bytes are
// read as a validation report (ParseValidationReport, then ValidationSection)
// and as bundle statistics (nesting check, parse, CheckBundleStats, then
// BundleStatsSection). Every input is refused with lsds::Error or written;
// what is written must hold only the tags the writers emit: a tag of the input
// in the page (an escape missed) aborts, as a crash would.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>

#include "libs/collection/model.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"
#include "libs/util/limits.h"
#include "report/bundle_section.h"
#include "report/validation_section.h"

namespace {

// Every '<' of the section starts one of the writers' own tags.
void CheckTags(const std::string& html) {
  static const std::set<std::string> kTags = {"a",
                                              "br",
                                              "code",
                                              "div",
                                              "h2",
                                              "h3",
                                              "p",
                                              "section",
                                              "small",
                                              "span",
                                              "table",
                                              "td",
                                              "th",
                                              "tr"};
  for (size_t at = html.find('<'); at != std::string::npos; at = html.find('<', at + 1)) {
    size_t begin = at + 1;
    if (begin < html.size() && html[begin] == '/') ++begin;
    size_t end = begin;
    while (end < html.size() &&
           ((html[end] >= 'a' && html[end] <= 'z') || (html[end] >= '0' && html[end] <= '9'))) {
      ++end;
    }
    const std::string tag = html.substr(begin, end - begin);
    if (kTags.count(tag) == 0 || end >= html.size() || (html[end] != '>' && html[end] != ' ')) {
      std::fprintf(stderr, "unexpected markup at %zu: %s\n", at, html.substr(at, 80).c_str());
      std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const lsds::report::ValidationSummary summary =
        lsds::report::ParseValidationReport(text, "fuzz.json");
    const std::set<int64_t> on_sheet = lsds::report::FramesWithFindings(summary, 12);
    CheckTags(lsds::report::ValidationSection(summary, on_sheet).str());
  } catch (const lsds::Error&) {
  }
  try {
    const std::string copy(text);
    lsds::CheckJsonNesting(copy, "fuzz.json");
    const nlohmann::json stats = lsds::ParseJsonText(text, "fuzz.json");
    lsds::report::CheckBundleStats(stats, "fuzz.json");
    lsds::CollectionHeader header;
    header.classes = {{1, "<script>x</script>"}, {2, "crate"}};
    CheckTags(lsds::report::BundleStatsSection(stats, header).str());
  } catch (const lsds::Error&) {
  }
  return 0;
}
