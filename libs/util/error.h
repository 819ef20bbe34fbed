// Errors that name the place: every message a user sees says which file and
// where in it.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace lsds {

// Where in an input something went wrong. Only the fields that apply are set.
struct Location {
  Location() = default;
  explicit Location(std::string file_path) : file(std::move(file_path)) {}
  Location(std::string file_path, std::string pointer)
      : file(std::move(file_path)), json_pointer(std::move(pointer)) {}
  static Location Text(std::string file_path, int line, int column) {
    Location location(std::move(file_path));
    location.line = line;
    location.column = column;
    return location;
  }
  static Location Pixel(std::string file_path, int64_t frame, int x, int y) {
    Location location(std::move(file_path));
    location.frame = frame;
    location.pixel_x = x;
    location.pixel_y = y;
    return location;
  }

  std::string file;
  int line = 0;    // 1-based, text inputs
  int column = 0;  // 1-based, text inputs
  std::string json_pointer;
  std::optional<int64_t> frame;
  std::optional<int> pixel_x, pixel_y;

  // "collection.json:12:5", "collection.json#/frames/3/camera",
  // "depth/000003.exr frame 3 pixel (10, 4)".
  std::string ToString() const;
};

// Process exit codes, the same for every command.
enum ExitCode : int {
  kExitOk = 0,
  kExitFindings = 1,  // the data has findings at or above the failure level
  kExitUsage = 2,     // bad usage or unreadable input
  // A bug in lsds: a failed internal check (libs/util/check.h) or an
  // unexpected exception. 70 is EX_SOFTWARE of sysexits.h.
  kExitInternal = 70,
};

// Bad input or bad usage: reported to the user with its location, exit code 2.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, Location location = {});
  const Location& location() const { return location_; }
  const std::string& message() const { return message_; }

 private:
  std::string message_;
  Location location_;
};

// Converts a byte offset inside `text` into 1-based line and column.
void LineColumnFromOffset(const std::string& text, size_t offset, int* line, int* column);

}  // namespace lsds
