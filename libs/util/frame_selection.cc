#include "libs/util/frame_selection.h"

#include <algorithm>

#include "libs/util/error.h"

namespace lsds {

namespace {

const char kForms[] =
    "expected A:B (indices A to B-1), A:, :B or N (the single frame N), with "
    "frame indices >= 0";

}  // namespace

FrameSelection ParseFrameSelection(const std::string& text, const std::string& flag) {
  const std::string where = flag + " " + text;
  auto parse = [&](const std::string& part, int64_t fallback) -> int64_t {
    if (part.empty()) return fallback;
    size_t used = 0;
    long long value = -1;
    try {
      value = std::stoll(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != part.size() || value < 0 || part[0] == '+' || part[0] == ' ')
      throw Error(std::string(kForms) + "; got '" + text + "'", Location(where));
    return value;
  };
  FrameSelection selection;
  selection.text = text;
  const size_t colon = text.find(':');
  if (text.empty() || text == ":" ||
      (colon != std::string::npos && text.find(':', colon + 1) != std::string::npos)) {
    if (text == ":") return selection;  // every frame, as in Python
    throw Error(std::string(kForms) + "; got '" + text + "'", Location(where));
  }
  if (colon == std::string::npos) {
    selection.begin = parse(text, 0);
    selection.end = selection.begin + 1;
  } else {
    selection.begin = parse(text.substr(0, colon), 0);
    selection.end = parse(text.substr(colon + 1), FrameSelection::kToTheEnd);
  }
  if (selection.end <= selection.begin) {
    throw Error(
        "the range is empty: B must be greater than A (A:B selects "
        "indices A to B-1)",
        Location(where));
  }
  return selection;
}

void CheckFrameSelection(const FrameSelection& selection,
                         const std::vector<int64_t>& available,
                         const std::string& what,
                         const std::string& flag) {
  const std::string where = flag + " " + selection.text;
  if (available.empty()) throw Error(what + " has no frames", Location(where));
  const int64_t first = available.front(), last = available.back();
  const std::string valid = what + " has frame indices " + std::to_string(first) + " to " +
                            std::to_string(last) + " (" + std::to_string(available.size()) +
                            " frames; " + flag + " " + std::to_string(first) + ":" +
                            std::to_string(last + 1) + " selects them all)";
  if (selection.begin < first || selection.begin > last ||
      (selection.bounded() && selection.end > last + 1)) {
    throw Error("out of range: " + valid, Location(where));
  }
  const auto it = std::lower_bound(available.begin(), available.end(), selection.begin);
  if (it == available.end() || !selection.Contains(*it))
    throw Error("selects no frame: " + valid, Location(where));
}

}  // namespace lsds
