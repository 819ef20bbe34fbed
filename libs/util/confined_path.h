// The one confinement rule for every reader of foreign data (docs/import.md,
// "Confinement"): a path written in a source's data (a JSON field, a CSV cell)
// is relative with no ".." component, and every file read from a source, named
// by its data or by its format's layout, resolves (symbolic links followed)
// inside the source folder. Otherwise a crafted source could make lsds read
// any file the user can read (/etc/..., ~/.ssh/...) and copy it into the
// output. Data that deliberately links elsewhere is read with an explicit flag
// (`lsds import --allow-links-outside`), which relaxes the symlink rule only.
#pragma once

#include <filesystem>
#include <string>

#include "libs/util/error.h"

namespace lsds {

// Why `reference` (a path written in data) is not a relative path inside its
// folder (`folder` names it: "the collection", "the source"): "is empty", "is
// absolute", "leaves the collection (\"..\")", "holds a NUL byte"; "" when it
// is fine. Backslashes count as separators, so a reference
// written on Windows is judged alike. The lexical half of the rule, shared with
// the collection's own file references (docs/format.md, "File references").
std::string ReferenceProblem(const std::string& reference, const std::string& folder);

class ConfinedFolder {
 public:
  // `root` must exist. With `allow_links_outside`, symbolic links may resolve
  // outside `root`; references in data must still be relative and inside.
  explicit ConfinedFolder(const std::filesystem::path& root, bool allow_links_outside = false);

  const std::filesystem::path& root() const { return root_; }
  bool allow_links_outside() const { return allow_links_outside_; }

  // `path` (built by the caller from root(): a file its format's layout names,
  // or an entry of a listed folder) when it resolves inside root() and is a
  // regular file or absent (the reader then reports it missing); throws
  // lsds::Error at `where` naming the path and where it leads otherwise. A
  // FIFO or device is refused here too: reading it would block.
  std::filesystem::path File(const std::filesystem::path& path, const Location& where) const;
  std::filesystem::path File(const std::filesystem::path& path) const {
    return File(path, Location(path.string()));
  }

  // The file `reference` (text read from the source's data at `where`) names
  // relative to `base` (root() or a folder below it): refused unless
  // ReferenceProblem is "", then checked as File.
  std::filesystem::path Reference(const std::filesystem::path& base,
                                  const std::string& reference,
                                  const Location& where) const;

 private:
  std::filesystem::path root_;       // as given
  std::filesystem::path canonical_;  // absolute, symlinks resolved
  bool allow_links_outside_;
};

}  // namespace lsds
