#include "libs/util/path_overlap.h"

#include <algorithm>

#include "libs/util/error.h"

namespace lsds {

namespace fs = std::filesystem;

namespace {

fs::path Resolved(const fs::path& path) {
  const fs::path p = fs::weakly_canonical(fs::absolute(path));
  return p.filename().empty() ? p.parent_path() : p;  // "coll/" == "coll"
}

}  // namespace

bool PathIsWithin(const fs::path& inner, const fs::path& outer) {
  const fs::path in = Resolved(inner), out = Resolved(outer);
  return std::mismatch(out.begin(), out.end(), in.begin(), in.end()).first ==
         out.end();
}

void RefuseOutputOverlappingInput(const fs::path& input,
                                  const fs::path& output,
                                  const std::string& what) {
  if (PathIsWithin(output, input) || PathIsWithin(input, output)) {
    throw Error("the output must neither be, lie inside nor contain the " +
                    what + " '" + input.string() + "'",
                Location(output.string()));
  }
}

}  // namespace lsds
