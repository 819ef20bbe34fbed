#include "libs/util/error.h"

#include <sstream>

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
  if (pixel_x && pixel_y)
    out << " pixel (" << *pixel_x << ", " << *pixel_y << ")";
  return out.str();
}

static std::string Compose(const std::string& message,
                           const Location& location) {
  const std::string where = location.ToString();
  return where.empty() ? message : where + ": " + message;
}

Error::Error(const std::string& message, Location location)
    : std::runtime_error(Compose(message, location)),
      message_(message),
      location_(std::move(location)) {}

void LineColumnFromOffset(const std::string& text,
                          size_t offset,
                          int* line,
                          int* column) {
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
