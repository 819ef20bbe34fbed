#include "libs/util/input_file.h"

#include "libs/util/error.h"

namespace lsds {

namespace fs = std::filesystem;

void RequireRegularFile(const fs::path& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || status.type() == fs::file_type::not_found) {
    throw Error("cannot read the " + what + ": it does not exist", Location(path.string()));
  }
  if (status.type() == fs::file_type::directory) {
    throw Error("the " + what + " is a folder, expected a file", Location(path.string()));
  }
  if (status.type() != fs::file_type::regular) {
    throw Error("the " + what +
                    " is not a regular file (a FIFO, socket or device); lsds "
                    "reads only regular files",
                Location(path.string()));
  }
}

}  // namespace lsds
