#include "libs/util/output_guard.h"

#include "libs/util/error.h"

namespace lsds {

namespace fs = std::filesystem;

fs::path CanonicalPath(const fs::path& path) {
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  if (ec) absolute = path;
  fs::path canonical = fs::weakly_canonical(absolute, ec);
  if (ec) canonical = absolute;
  return canonical.lexically_normal();
}

bool PathWithin(const fs::path& inner, const fs::path& outer) {
  auto in = inner.begin();
  for (auto out = outer.begin(); out != outer.end(); ++out, ++in) {
    // A trailing "/" leaves an empty last component: it matches anything.
    if (out->empty() && std::next(out) == outer.end()) return true;
    if (in == inner.end() || *in != *out) return false;
  }
  return true;
}

OutputGuard::OutputGuard(std::string command) : command_(std::move(command)) {}

void OutputGuard::AddInput(const fs::path& path, const std::string& what) {
  if (path.empty()) return;
  inputs_.push_back({path, CanonicalPath(path), what, false});
}

void OutputGuard::AddContainer(const fs::path& folder, const std::string& what) {
  if (folder.empty()) return;
  inputs_.push_back({folder, CanonicalPath(folder), what, true});
}

void OutputGuard::AddSymlinkTargetsIn(const fs::path& folder) {
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (it->is_symlink(type_ec)) {
      inputs_.push_back({it->path(), CanonicalPath(it->path()), "target of the symlink", false});
    }
  }
}

void OutputGuard::CheckOutput(const fs::path& output, const std::string& flag) const {
  if (output.empty()) return;
  const fs::path out = CanonicalPath(output);
  std::error_code ec;
  const bool exists = fs::exists(output, ec);
  // "is" first, whichever input it is: `-o C` is the collection folder, even
  // though it also contains collection.json.
  auto relation_to = [&](const Entry& input, bool identity) -> std::string {
    if (identity) {
      const bool same =
          out == input.canonical || (exists && fs::equivalent(output, input.given, ec));
      return same ? "is" : "";
    }
    if (PathWithin(input.canonical, out)) return "contains";
    if (!input.container && PathWithin(out, input.canonical)) return "lies inside";
    return "";
  };
  for (const bool identity : {true, false}) {
    for (const Entry& input : inputs_) {
      const std::string relation = relation_to(input, identity);
      if (relation.empty()) continue;
      std::string message = "the output";
      if (!flag.empty()) message += " (" + flag + ")";
      message += " " + relation + " the " + input.what + " " + input.given.string();
      if (input.given != input.canonical) message += " (" + input.canonical.string() + ")";
      message += ", an input of " + command_ +
                 "; an output may not be, contain or lie inside an input, even "
                 "with --force: choose another output";
      throw Error(message, Location(output.string()));
    }
  }
}

}  // namespace lsds
