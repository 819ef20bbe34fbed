#include "libs/exr/deep_image.h"

#include <ImfChannelList.h>
#include <ImfDeepFrameBuffer.h>
#include <ImfDeepScanLineInputFile.h>
#include <ImfDeepScanLineOutputFile.h>
#include <ImfPartType.h>
#include <half.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "libs/exr/exr_internal.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/limits.h"

namespace lsds::exr {

DeepImage::DeepImage(int width, int height, std::vector<uint32_t> sample_counts) {
  Reshape(width, height, sample_counts.begin(), sample_counts.end());
}

void DeepImage::Reshape(int width,
                        int height,
                        std::vector<uint32_t>::const_iterator first_count,
                        std::vector<uint32_t>::const_iterator last_count) {
  width_ = width;
  height_ = height;
  sample_counts_.assign(first_count, last_count);
  if (sample_counts_.size() != pixel_count())
    throw Error("deep image: sample count array size mismatch");
  offsets_.resize(pixel_count() + 1);
  offsets_[0] = 0;
  for (size_t i = 0; i < pixel_count(); ++i) offsets_[i + 1] = offsets_[i] + sample_counts_[i];
  for (DeepChannel& channel : channels_) {
    if (channel.type == PixelType::kUint) {
      channel.uints.assign(total_samples(), 0u);
    } else {
      channel.floats.assign(total_samples(), 0.0f);
    }
  }
}

DeepChannel& DeepImage::AddChannel(const std::string& name, PixelType type) {
  channels_.push_back({name, type, {}, {}});
  DeepChannel& channel = channels_.back();
  if (type == PixelType::kUint) {
    channel.uints.assign(total_samples(), 0u);
  } else {
    channel.floats.assign(total_samples(), 0.0f);
  }
  return channel;
}

void DeepImage::AddChannels(const std::vector<ChannelSpec>& specs) {
  const size_t first = channels_.size();
  for (const ChannelSpec& spec : specs) channels_.push_back({spec.name, spec.type, {}, {}});
  tbb::parallel_for(first, channels_.size(), [&](size_t c) {
    DeepChannel& channel = channels_[c];
    if (channel.type == PixelType::kUint) {
      channel.uints.assign(total_samples(), 0u);
    } else {
      channel.floats.assign(total_samples(), 0.0f);
    }
  });
}

const DeepChannel* DeepImage::Find(const std::string& name) const {
  for (const DeepChannel& channel : channels_) {
    if (channel.name == name) return &channel;
  }
  return nullptr;
}

const DeepChannel& DeepImage::Get(const std::string& name) const {
  const DeepChannel* channel = Find(name);
  if (channel == nullptr) throw Error("deep image has no channel '" + name + "'");
  return *channel;
}

DeepChannel& DeepImage::Get(const std::string& name) {
  return const_cast<DeepChannel&>(static_cast<const DeepImage*>(this)->Get(name));
}

namespace {

// OpenEXR's deep frame buffers take one pointer per pixel into each channel's
// sample storage.
template <typename T>
void PixelPointers(T* samples, const std::vector<uint64_t>& offsets, std::vector<char*>* pointers) {
  pointers->resize(offsets.size() - 1);
  for (size_t i = 0; i + 1 < offsets.size(); ++i) {
    (*pointers)[i] = reinterpret_cast<char*>(samples + offsets[i]);
  }
}

template <typename T>
std::vector<char*> PixelPointers(T* samples, const std::vector<uint64_t>& offsets) {
  std::vector<char*> pointers;
  PixelPointers(samples, offsets, &pointers);
  return pointers;
}

}  // namespace

DeepImage ReadDeepExr(const std::filesystem::path& path,
                      const std::vector<std::string>& channels,
                      const ReadLimits& limits) {
  return internal::GuardExr(path, [&] {
    const Location where{path.string()};
    RequireRegularFile(path, "layer file");
    internal::ScanHeader(path, limits);
    Imf::DeepScanLineInputFile file(path.c_str());
    const Imf::Header& header = file.header();
    internal::CheckLimits(path, header, limits);
    const ExrInfo info = internal::InfoFromHeader(header);
    const int width = info.width, height = info.height;

    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    CheckMemoryBudget(4.0 * width * height, "decoding the sample counts of " + size, path.string());
    Imf::DeepFrameBuffer counts_buffer;
    std::vector<uint32_t> sample_counts(static_cast<size_t>(width) * height);
    counts_buffer.insertSampleCountSlice(Imf::Slice(Imf::UINT,
                                                    reinterpret_cast<char*>(sample_counts.data()),
                                                    sizeof(uint32_t),
                                                    sizeof(uint32_t) * width));
    file.setFrameBuffer(counts_buffer);
    file.readPixelSampleCounts(0, height - 1);
    uint64_t total = 0;
    for (size_t i = 0; i < sample_counts.size(); ++i) {
      if (sample_counts[i] > static_cast<uint32_t>(limits.max_samples_per_pixel)) {
        throw Error("pixel (" + std::to_string(i % width) + ", " + std::to_string(i / width) +
                        ") has " + std::to_string(sample_counts[i]) + " samples, beyond the limit",
                    where);
      }
      total += sample_counts[i];
    }
    if (total > static_cast<uint64_t>(limits.max_deep_samples)) {
      throw Error(std::to_string(total) + " deep samples exceed the reader's limit", where);
    }

    std::vector<ChannelSpec> wanted;
    if (channels.empty()) {
      wanted = info.channels;
    } else {
      for (const std::string& name : channels) {
        const ChannelSpec* spec = info.Find(name);
        if (spec == nullptr) throw Error("has no channel '" + name + "'", where);
        wanted.push_back(*spec);
      }
    }
    // 4 bytes per sample and channel, a pointer per pixel and channel for
    // OpenEXR's deep slices, and the pixel offsets.
    CheckMemoryBudget(4.0 * static_cast<double>(total) * static_cast<double>(wanted.size()) +
                          8.0 * width * height * static_cast<double>(wanted.size() + 1),
                      "decoding " + std::to_string(total) + " deep samples of " +
                          std::to_string(wanted.size()) + " channel(s) in " + size,
                      path.string());
    DeepImage image(width, height, std::move(sample_counts));
    Imf::DeepFrameBuffer frame_buffer;
    frame_buffer.insertSampleCountSlice(
        Imf::Slice(Imf::UINT,
                   reinterpret_cast<char*>(const_cast<uint32_t*>(image.sample_counts().data())),
                   sizeof(uint32_t),
                   sizeof(uint32_t) * width));
    std::vector<std::vector<char*>> pointers;
    pointers.reserve(wanted.size());
    for (const ChannelSpec& spec : wanted) {
      DeepChannel& channel = image.AddChannel(spec.name, spec.type);
      const bool is_uint = spec.type == PixelType::kUint;
      pointers.push_back(is_uint ? PixelPointers(channel.uints.data(), image.offsets())
                                 : PixelPointers(channel.floats.data(), image.offsets()));
      const size_t element = is_uint ? sizeof(uint32_t) : sizeof(float);
      frame_buffer.insert(spec.name,
                          Imf::DeepSlice(is_uint ? Imf::UINT : Imf::FLOAT,
                                         reinterpret_cast<char*>(pointers.back().data()),
                                         sizeof(char*),
                                         sizeof(char*) * width,
                                         element));
    }
    file.setFrameBuffer(frame_buffer);
    file.readPixelSampleCounts(0, height - 1);  // a new frame buffer needs its counts read again
    file.readPixels(0, height - 1);
    return image;
  });
}

namespace {

void CheckDeepCompression(const std::filesystem::path& path, const WriteOptions& options) {
  if (options.compression != Compression::kNone && options.compression != Compression::kRle &&
      options.compression != Compression::kZips) {
    throw Error(std::string("deep EXR files allow only none, rle or zips compression, not ") +
                    CompressionName(options.compression),
                Location(path.string()));
  }
}

Imf::Header DeepHeader(int width,
                       int height,
                       const std::vector<ChannelSpec>& channels,
                       const WriteOptions& options) {
  Imf::Header header(width, height);
  header.compression() = internal::ToImf(options.compression);
  header.setType(Imf::DEEPSCANLINE);
  internal::AddCamera(options, &header);
  internal::AddAttributes(options, &header);
  for (const ChannelSpec& channel : channels)
    header.channels().insert(channel.name, Imf::Channel(internal::ToImf(channel.type)));
  return header;
}

// A frame buffer address for row `first_row` onwards: OpenEXR addresses pixel
// (x, y) at base + y * y_stride, so a band that starts at `first_row` passes
// its storage moved back by that many rows, as OpenEXR's own Slice::Make does
// for a data window that does not start at 0. Only rows of the band are
// dereferenced.
char* RowOrigin(const void* band, int first_row, size_t y_stride) {
  return static_cast<char*>(const_cast<void*>(band)) -
         static_cast<ptrdiff_t>(first_row) * static_cast<ptrdiff_t>(y_stride);
}

// Writes `band`, rows [first_row, first_row + band.height()) of the file;
// `pointers` is scratch for the per-pixel pointers, kept from band to band.
void WriteBand(Imf::DeepScanLineOutputFile* file,
               const DeepImage& band,
               int first_row,
               std::vector<std::vector<char*>>* pointers) {
  const int width = band.width();
  Imf::DeepFrameBuffer frame_buffer;
  frame_buffer.insertSampleCountSlice(
      Imf::Slice(Imf::UINT,
                 RowOrigin(band.sample_counts().data(), first_row, sizeof(uint32_t) * width),
                 sizeof(uint32_t),
                 sizeof(uint32_t) * width));
  std::vector<std::vector<half>> halves;
  halves.reserve(band.channels().size());
  pointers->resize(band.channels().size());
  for (size_t c = 0; c < band.channels().size(); ++c) {
    const DeepChannel& channel = band.channels()[c];
    std::vector<char*>& pixel_pointers = (*pointers)[c];
    size_t element = 4;
    if (channel.type == PixelType::kUint) {
      PixelPointers(const_cast<uint32_t*>(channel.uints.data()), band.offsets(), &pixel_pointers);
    } else if (channel.type == PixelType::kFloat) {
      PixelPointers(const_cast<float*>(channel.floats.data()), band.offsets(), &pixel_pointers);
    } else {
      halves.emplace_back(channel.floats.begin(), channel.floats.end());
      PixelPointers(halves.back().data(), band.offsets(), &pixel_pointers);
      element = sizeof(half);
    }
    frame_buffer.insert(
        channel.name,
        Imf::DeepSlice(internal::ToImf(channel.type),
                       RowOrigin(pixel_pointers.data(), first_row, sizeof(char*) * width),
                       sizeof(char*),
                       sizeof(char*) * width,
                       element));
  }
  file->setFrameBuffer(frame_buffer);
  file->writePixels(band.height());
}

std::vector<ChannelSpec> SpecsOf(const DeepImage& image) {
  std::vector<ChannelSpec> specs;
  for (const DeepChannel& channel : image.channels()) specs.push_back({channel.name, channel.type});
  return specs;
}

}  // namespace

void WriteDeepExr(const std::filesystem::path& path,
                  const DeepImage& image,
                  const WriteOptions& options) {
  CheckDeepCompression(path, options);
  internal::WriteAtomicExr(path, [&](Imf::OStream& stream) {
    Imf::DeepScanLineOutputFile file(
        stream, DeepHeader(image.width(), image.height(), SpecsOf(image), options));
    std::vector<std::vector<char*>> pointers;
    WriteBand(&file, image, 0, &pointers);
  });
}

void WriteDeepExrInBands(const std::filesystem::path& path,
                         int width,
                         const std::vector<uint32_t>& sample_counts,
                         const std::vector<ChannelSpec>& channels,
                         const DeepBandFiller& fill,
                         const WriteOptions& options,
                         int band_rows) {
  CheckDeepCompression(path, options);
  if (width <= 0 || sample_counts.size() % static_cast<size_t>(width) != 0 || band_rows <= 0)
    throw Error("deep image: sample count array size mismatch", Location(path.string()));
  const int height = static_cast<int>(sample_counts.size() / static_cast<size_t>(width));
  internal::WriteAtomicExr(path, [&](Imf::OStream& stream) {
    Imf::DeepScanLineOutputFile file(stream, DeepHeader(width, height, channels, options));
    // One band's storage, reused: memory stays one band's, and its pages
    // are touched once per file, not once per band.
    DeepImage band;
    for (const ChannelSpec& channel : channels) band.AddChannel(channel.name, channel.type);
    std::vector<std::vector<char*>> pointers;
    for (int first_row = 0; first_row < height; first_row += band_rows) {
      const int rows = std::min(band_rows, height - first_row);
      const auto counts = sample_counts.begin() + static_cast<ptrdiff_t>(first_row) * width;
      band.Reshape(width, rows, counts, counts + static_cast<ptrdiff_t>(rows) * width);
      fill(first_row, &band);
      WriteBand(&file, band, first_row, &pointers);
    }
  });
}

}  // namespace lsds::exr
