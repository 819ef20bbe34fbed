// Flat (one value per pixel and channel) EXR layers: read and write typed
// channels by name.
#pragma once

#include <deque>
#include <filesystem>
#include <string>
#include <vector>

#include "libs/exr/exr_types.h"

namespace lsds::exr {

// One channel, stored row-major. HALF and FLOAT channels decode to `floats`,
// UINT ones to `uints`.
struct FlatChannel {
  std::string name;
  PixelType type = PixelType::kFloat;
  std::vector<float> floats;
  std::vector<uint32_t> uints;
};

class FlatImage {
 public:
  FlatImage() = default;
  FlatImage(int width, int height) : width_(width), height_(height) {}

  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixel_count() const { return static_cast<size_t>(width_) * height_; }

  // Adds a zero-filled channel (replacing one with the same name) and returns
  // it.
  FlatChannel& AddChannel(const std::string& name, PixelType type);
  // The same for several channels, filled in parallel: a large image's fresh
  // pages are first touched (faulted in and zeroed) by every core, not one.
  void AddChannels(const std::vector<ChannelSpec>& specs);
  const FlatChannel* Find(const std::string& name) const;
  FlatChannel* Find(const std::string& name);
  const FlatChannel& Get(const std::string& name) const;  // throws lsds::Error when missing
  FlatChannel& Get(const std::string& name);
  const std::deque<FlatChannel>& channels() const { return channels_; }

  float& F(const std::string& name, int x, int y) { return Get(name).floats[Index(x, y)]; }
  uint32_t& U(const std::string& name, int x, int y) { return Get(name).uints[Index(x, y)]; }
  size_t Index(int x, int y) const { return static_cast<size_t>(y) * width_ + x; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::deque<FlatChannel> channels_;  // deque: AddChannel keeps earlier references valid
};

// Reads the named channels (all when `channels` is empty) of a flat scanline
// EXR, each decoded into its file type's storage. Throws lsds::Error naming the
// file for missing channels, deep or tiled files, files beyond `limits`
// (checked before decoding) and decoding failures.
FlatImage ReadFlatExr(const std::filesystem::path& path,
                      const std::vector<std::string>& channels = {},
                      const ReadLimits& limits = {});

// Writes atomically (temporary file + rename).
void WriteFlatExr(const std::filesystem::path& path,
                  const FlatImage& image,
                  const WriteOptions& options = {});

}  // namespace lsds::exr
