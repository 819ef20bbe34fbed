// One EXR file of another renderer, single-part multilayer or multipart:
// channels found by name in whichever part holds them, header attributes of
// every part as text. Limits are checked on the header before any pixel is
// decoded (libs/exr ReadLimits).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "libs/exr/exr_types.h"

namespace lsds::import {

class SourceExr {
 public:
  // Throws lsds::Error naming the file when it is not a readable flat EXR,
  // parts disagree on their data window, or it is beyond `limits`.
  explicit SourceExr(const std::filesystem::path& path, const exr::ReadLimits& limits = {});

  int width() const { return width_; }
  int height() const { return height_; }
  // The data window's top-left pixel, and part 0's display window (origin
  // and size), in the file's pixel coordinates.
  int data_min_x() const { return min_x_; }
  int data_min_y() const { return min_y_; }
  struct Window {
    int min_x = 0, min_y = 0, width = 0, height = 0;
  };
  const Window& display_window() const { return display_; }
  const std::string& file() const { return file_; }
  bool HasChannel(const std::string& name) const { return channels_.count(name) != 0; }
  std::optional<exr::PixelType> ChannelType(const std::string& name) const;
  std::vector<std::string> ChannelNames() const;

  // String, float, double and int attributes of every part, as text (numbers
  // with round-trip precision). The first part that has a name wins.
  const std::map<std::string, std::string>& attributes() const { return attributes_; }
  // The number in the first attribute of `names` that exists; throws naming
  // the file and the names when none does or it is not a number.
  double Number(const std::vector<std::string>& names) const;

  // Row-major, top row first. HALF and FLOAT channels are decoded to float (a
  // FLOAT channel keeps its bits); throws for a missing or UINT channel.
  std::vector<float> ReadFloat(const std::string& channel) const;

 private:
  struct ChannelPlace {
    int part = 0;
    exr::PixelType type = exr::PixelType::kFloat;
  };
  std::filesystem::path path_;
  std::string file_;
  int width_ = 0, height_ = 0;
  int min_x_ = 0, min_y_ = 0;
  Window display_;
  std::map<std::string, ChannelPlace> channels_;
  std::map<std::string, std::string> attributes_;
};

}  // namespace lsds::import
