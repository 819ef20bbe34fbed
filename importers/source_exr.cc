#include "importers/source_exr.h"

#include <cstdio>
#include <cstdlib>

#include <ImfAttribute.h>
#include <ImfChannelList.h>
#include <ImfDoubleAttribute.h>
#include <ImfFloatAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfIntAttribute.h>
#include <ImfMultiPartInputFile.h>
#include <ImfPartType.h>
#include <ImfStringAttribute.h>

#include "libs/exr/exr_info.h"
#include "libs/util/error.h"
#include "libs/util/limits.h"
#include "libs/util/strings.h"

namespace lsds::import {

namespace {
// All 17 significant digits: a header value read back as text loses nothing.
std::string NumberText(double value) { return FormatNumber(value, 17); }

// Part 0's display window, checked against the limits like the data window.
SourceExr::Window DisplayWindowOf(const Imf::Header& header,
                                  const exr::ReadLimits& limits,
                                  const std::string& file) {
  const Imath::Box2i& display = header.displayWindow();
  const int64_t w = int64_t{display.max.x} - display.min.x + 1;
  const int64_t h = int64_t{display.max.y} - display.min.y + 1;
  if (w < 1 || h < 1 || w > limits.max_width || h > limits.max_height)
    throw Error("display window " + std::to_string(w) + "x" + std::to_string(h) +
                    " is empty or beyond the limits",
                Location(file));
  return {display.min.x, display.min.y, static_cast<int>(w), static_cast<int>(h)};
}
}  // namespace

SourceExr::SourceExr(const std::filesystem::path& path, const exr::ReadLimits& limits)
    : path_(path), file_(path.string()) {
  // OpenEXR allocates what the header declares while it opens the file.
  exr::CheckExrHeader(path, limits);
  try {
    Imf::MultiPartInputFile input(file_.c_str());
    for (int part = 0; part < input.parts(); ++part) {
      const Imf::Header& header = input.header(part);
      if (header.hasType() && header.type() != Imf::SCANLINEIMAGE &&
          header.type() != Imf::TILEDIMAGE)
        throw Error("part " + std::to_string(part) + " is deep; a flat EXR was expected",
                    Location(file_));
      const Imath::Box2i& window = header.dataWindow();
      const int64_t w = int64_t{window.max.x} - window.min.x + 1;
      const int64_t h = int64_t{window.max.y} - window.min.y + 1;
      if (w < 1 || h < 1 || w > limits.max_width || h > limits.max_height ||
          w * h > limits.max_pixels)
        throw Error("data window " + std::to_string(w) + "x" + std::to_string(h) +
                        " is empty or beyond the limits",
                    Location(file_));
      if (part == 0) {
        width_ = static_cast<int>(w), height_ = static_cast<int>(h);
        min_x_ = window.min.x, min_y_ = window.min.y;
        display_ = DisplayWindowOf(header, limits, file_);
      } else if (w != width_ || h != height_ || window.min.x != min_x_ || window.min.y != min_y_) {
        throw Error("part " + std::to_string(part) + " has another data window than part 0",
                    Location(file_));
      }
      for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
        if (channels_.size() >= static_cast<size_t>(limits.max_channels) * 8)
          throw Error("too many channels", Location(file_));
        exr::PixelType type = exr::PixelType::kFloat;
        if (c.channel().type == Imf::UINT) type = exr::PixelType::kUint;
        if (c.channel().type == Imf::HALF) type = exr::PixelType::kHalf;
        if (c.channel().xSampling != 1 || c.channel().ySampling != 1)
          throw Error("channel '" + std::string(c.name()) + "' is subsampled", Location(file_));
        channels_.emplace(c.name(), ChannelPlace{part, type});
      }
      for (auto a = header.begin(); a != header.end(); ++a) {
        const std::string name = a.name();
        if (attributes_.count(name)) continue;
        const Imf::Attribute& value = a.attribute();
        if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&value))
          attributes_[name] = s->value();
        else if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&value))
          attributes_[name] = NumberText(f->value());
        else if (const auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&value))
          attributes_[name] = NumberText(d->value());
        else if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&value))
          attributes_[name] = std::to_string(i->value());
      }
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(std::string("not a readable EXR: ") + e.what(), Location(file_));
  }
}

std::optional<exr::PixelType> SourceExr::ChannelType(const std::string& name) const {
  const auto it = channels_.find(name);
  if (it == channels_.end()) return std::nullopt;
  return it->second.type;
}

std::vector<std::string> SourceExr::ChannelNames() const {
  std::vector<std::string> names;
  for (const auto& entry : channels_) names.push_back(entry.first);
  return names;
}

double SourceExr::Number(const std::vector<std::string>& names) const {
  for (const std::string& name : names) {
    const auto it = attributes_.find(name);
    if (it == attributes_.end()) continue;
    char* end = nullptr;
    const double value = std::strtod(it->second.c_str(), &end);
    if (end == it->second.c_str() || *end != '\0')
      throw Error("header attribute '" + name + "' is '" + it->second + "', not a number",
                  Location(file_));
    return value;
  }
  throw Error("header attribute missing: none of " + Join(names, ", "), Location(file_));
}

std::vector<float> SourceExr::ReadFloat(const std::string& channel) const {
  const auto it = channels_.find(channel);
  if (it == channels_.end())
    throw Error("channel '" + channel + "' missing" + DidYouMean(channel, ChannelNames()),
                Location(file_));
  if (it->second.type == exr::PixelType::kUint)
    throw Error("channel '" + channel + "' is UINT; a float was expected", Location(file_));
  CheckImageBudget(width_, height_, 1, sizeof(float), "decoding channel '" + channel + "'", file_);
  std::vector<float> pixels(static_cast<size_t>(width_) * height_);
  try {
    Imf::MultiPartInputFile input(file_.c_str());
    Imf::InputPart part(input, it->second.part);
    Imf::FrameBuffer buffer;
    // The buffer's origin is pixel (0, 0) of the data window.
    char* base =
        reinterpret_cast<char*>(pixels.data()) -
        (static_cast<ptrdiff_t>(min_y_) * width_ + min_x_) * static_cast<ptrdiff_t>(sizeof(float));
    buffer.insert(
        channel,
        Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * static_cast<size_t>(width_)));
    part.setFrameBuffer(buffer);
    part.readPixels(min_y_, min_y_ + height_ - 1);
  } catch (const std::exception& e) {
    throw Error("cannot decode channel '" + channel + "': " + e.what(), Location(file_));
  }
  return pixels;
}

}  // namespace lsds::import
