// Deep EXR layers: a variable-length list of samples per pixel (the pixel
// bundle of docs/format.md).
#pragma once

#include <deque>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "libs/exr/exr_types.h"

namespace lsds::exr {

// One channel's samples for all pixels, concatenated in pixel order
// (row-major), sample order within.
struct DeepChannel {
  std::string name;
  PixelType type = PixelType::kFloat;
  std::vector<float> floats;
  std::vector<uint32_t> uints;
};

class DeepImage {
 public:
  DeepImage() = default;
  // `sample_counts` has width * height entries.
  DeepImage(int width, int height, std::vector<uint32_t> sample_counts);

  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixel_count() const { return static_cast<size_t>(width_) * height_; }
  uint64_t total_samples() const { return offsets_.empty() ? 0 : offsets_.back(); }
  uint32_t SampleCount(int x, int y) const { return sample_counts_[Index(x, y)]; }
  // Index of the first sample of pixel (x, y) in every channel's arrays.
  uint64_t FirstSample(int x, int y) const { return offsets_[Index(x, y)]; }
  size_t Index(int x, int y) const { return static_cast<size_t>(y) * width_ + x; }
  const std::vector<uint32_t>& sample_counts() const { return sample_counts_; }
  const std::vector<uint64_t>& offsets() const { return offsets_; }

  // Another size and sample counts ([first_count, last_count), width * height
  // of them) for the same channels, zero-filled again; their storage is kept.
  void Reshape(int width,
               int height,
               std::vector<uint32_t>::const_iterator first_count,
               std::vector<uint32_t>::const_iterator last_count);
  DeepChannel& AddChannel(const std::string& name,
                          PixelType type);  // zero-filled
  // Adds zero-filled channels, filled in parallel: a large image's fresh pages
  // are first touched (faulted in and zeroed) by every core, not one.
  void AddChannels(const std::vector<ChannelSpec>& specs);
  const DeepChannel* Find(const std::string& name) const;
  const DeepChannel& Get(const std::string& name) const;  // throws lsds::Error when missing
  DeepChannel& Get(const std::string& name);
  const std::deque<DeepChannel>& channels() const { return channels_; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<uint32_t> sample_counts_;
  std::vector<uint64_t> offsets_;     // prefix sums, pixel_count() + 1 entries
  std::deque<DeepChannel> channels_;  // deque: AddChannel keeps earlier references valid
};

// Reads the named channels (all when empty) of a deep scanline EXR. Sample
// counts are checked against `limits` before any sample is decoded.
DeepImage ReadDeepExr(const std::filesystem::path& path,
                      const std::vector<std::string>& channels = {},
                      const ReadLimits& limits = {});

// Writes atomically (temporary file + rename). Deep files allow only none, rle
// or zips.
void WriteDeepExr(const std::filesystem::path& path,
                  const DeepImage& image,
                  const WriteOptions& options = {});

// Fills `band`, rows [first_row, first_row + band->height()) of a deep image:
// the band comes with its sample counts and zeroed channels.
using DeepBandFiller = std::function<void(int first_row, DeepImage* band)>;

// Writes a deep image that is produced a band of `band_rows` rows at a time,
// so that the writer holds one band, not the whole image (an encoder writing
// a layout, libs/collection/bundle_layout.cc). `sample_counts` are the whole
// image's, width * height of them, row-major; `channels` are the file's.
// Atomic and compressed as WriteDeepExr; the file is the one WriteDeepExr
// writes for the same samples.
void WriteDeepExrInBands(const std::filesystem::path& path,
                         int width,
                         const std::vector<uint32_t>& sample_counts,
                         const std::vector<ChannelSpec>& channels,
                         const DeepBandFiller& fill,
                         const WriteOptions& options = {},
                         int band_rows = 64);

}  // namespace lsds::exr
