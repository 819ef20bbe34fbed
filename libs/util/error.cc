#include "libs/util/error.h"

#include <sstream>

#include "libs/util/text_check.h"

namespace lsds {

std::string Location::ToString() const {
  std::ostringstream out;
  out << file;
  if (line > 0) {
    out << ":" << line;
    if (column > 0) out << ":" << column;
  }
  if (!json_pointer.empty()) out << "#" << json_pointer;
  if (frame) out << (out.tellp() > 0 ? " " : "") << "frame " << *frame;
  if (pixel_x && pixel_y) out << " pixel (" << *pixel_x << ", " << *pixel_y << ")";
  return out.str();
}

static std::string Compose(const std::string& message, const Location& location) {
  const std::string where = location.ToString();
  return where.empty() ? message : where + ": " + message;
}

// Messages quote inputs (identifiers, values, paths): they stay readable
// however long or binary the quoted text is.
static std::string Readable(const std::string& text) {
  return Excerpt(text, 2000, /*keep_lines=*/true);
}

static Location ReadableLocation(Location location) {
  location.file = Readable(location.file);
  location.json_pointer = Readable(location.json_pointer);
  return location;
}

Error::Error(const std::string& message, Location location)
    : std::runtime_error(Compose(Readable(message), ReadableLocation(location))),
      message_(Readable(message)),
      location_(ReadableLocation(std::move(location))) {}

void LineColumnFromOffset(const std::string& text, size_t offset, int* line, int* column) {
  *line = 1;
  *column = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++*line;
      *column = 1;
    } else {
      ++*column;
    }
  }
}

}  // namespace lsds
