#include "libs/util/confined_path.h"

#include <algorithm>
#include <cctype>
#include <system_error>

#include "libs/util/output_guard.h"
#include "libs/util/strings.h"
#include "libs/util/text_check.h"

namespace lsds {

namespace fs = std::filesystem;

std::string ReferenceProblem(const std::string& reference, const std::string& folder) {
  if (reference.empty()) return "is empty";
  if (reference.find('\0') != std::string::npos) return "holds a NUL byte";
  if (reference[0] == '/' || reference[0] == '\\' ||
      (reference.size() > 1 && std::isalpha(static_cast<unsigned char>(reference[0])) &&
       reference[1] == ':'))
    return "is absolute";
  std::string slashes = reference;  // "a\\..\\b" leaves it as well
  std::replace(slashes.begin(), slashes.end(), '\\', '/');
  for (const std::string& part : Split(slashes, '/'))
    if (part == "..") return "leaves " + folder + " (\"..\")";
  return "";
}

ConfinedFolder::ConfinedFolder(const fs::path& root, bool allow_links_outside)
    : root_(root), canonical_(CanonicalPath(root)), allow_links_outside_(allow_links_outside) {}

fs::path ConfinedFolder::File(const fs::path& path, const Location& where) const {
  const fs::path resolved = CanonicalPath(path);
  if (!allow_links_outside_ && !PathWithin(resolved, canonical_))
    throw Error("'" + path.string() + "' resolves to '" + resolved.string() +
                    "', outside the source folder '" + root_.string() +
                    "' (a symbolic link); lsds reads only files inside the source unless "
                    "--allow-links-outside is given",
                where);
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!ec && status.type() != fs::file_type::regular && status.type() != fs::file_type::not_found)
    throw Error(
        "'" + path.string() + "' is not a regular file (" +
            (status.type() == fs::file_type::directory ? "a folder" : "a FIFO, socket or device") +
            "); lsds reads only regular files",
        where);
  return path;
}

fs::path ConfinedFolder::Reference(const fs::path& base,
                                   const std::string& reference,
                                   const Location& where) const {
  const std::string problem = ReferenceProblem(reference, "the source");
  if (!problem.empty())
    throw Error("file name '" + Excerpt(reference) + "' " + problem +
                    "; names in a source must be relative paths inside it",
                where);
  return File(base / reference, where);
}

}  // namespace lsds
