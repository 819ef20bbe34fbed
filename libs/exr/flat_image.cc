#include "libs/exr/flat_image.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfPartType.h>
#include <half.h>

#include <tbb/parallel_for.h>
#include <algorithm>

#include "libs/exr/exr_internal.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/limits.h"

namespace lsds::exr {

namespace {

void ZeroFill(size_t pixels, FlatChannel* channel) {
  channel->floats.clear();
  channel->uints.clear();
  if (channel->type == PixelType::kUint) {
    channel->uints.assign(pixels, 0u);
  } else {
    channel->floats.assign(pixels, 0.0f);
  }
}

}  // namespace

FlatChannel& FlatImage::AddChannel(const std::string& name, PixelType type) {
  FlatChannel* channel = Find(name);
  if (channel == nullptr) {
    channels_.emplace_back();
    channel = &channels_.back();
  }
  channel->name = name;
  channel->type = type;
  ZeroFill(pixel_count(), channel);
  return *channel;
}

void FlatImage::AddChannels(const std::vector<ChannelSpec>& specs) {
  std::vector<FlatChannel*> added;
  for (const ChannelSpec& spec : specs) {
    FlatChannel* channel = Find(spec.name);
    if (channel == nullptr) {
      channels_.emplace_back();
      channel = &channels_.back();
    }
    channel->name = spec.name;
    channel->type = spec.type;
    if (std::find(added.begin(), added.end(), channel) == added.end()) added.push_back(channel);
  }
  tbb::parallel_for(size_t{0}, added.size(), [&](size_t c) { ZeroFill(pixel_count(), added[c]); });
}

const FlatChannel* FlatImage::Find(const std::string& name) const {
  for (const FlatChannel& channel : channels_) {
    if (channel.name == name) return &channel;
  }
  return nullptr;
}

FlatChannel* FlatImage::Find(const std::string& name) {
  return const_cast<FlatChannel*>(static_cast<const FlatImage*>(this)->Find(name));
}

const FlatChannel& FlatImage::Get(const std::string& name) const {
  const FlatChannel* channel = Find(name);
  if (channel == nullptr) throw Error("image has no channel '" + name + "'");
  return *channel;
}

FlatChannel& FlatImage::Get(const std::string& name) {
  return const_cast<FlatChannel&>(static_cast<const FlatImage*>(this)->Get(name));
}

FlatImage ReadFlatExr(const std::filesystem::path& path,
                      const std::vector<std::string>& channels,
                      const ReadLimits& limits) {
  return internal::GuardExr(path, [&] {
    RequireRegularFile(path, "layer file");
    internal::ScanHeader(path, limits);
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    if (header.hasType() && Imf::isDeepData(header.type())) {
      throw Error("is a deep EXR; expected a flat layer", Location(path.string()));
    }
    internal::CheckLimits(path, header, limits);
    const ExrInfo info = internal::InfoFromHeader(header);
    std::vector<ChannelSpec> wanted;
    if (channels.empty()) {
      wanted = info.channels;
    } else {
      for (const std::string& name : channels) {
        const ChannelSpec* spec = info.Find(name);
        if (spec == nullptr) throw Error("has no channel '" + name + "'", Location(path.string()));
        wanted.push_back(*spec);
      }
    }
    // Every channel decodes to 4 bytes per pixel (HALF to float).
    CheckMemoryBudget(4.0 * info.width * info.height * static_cast<double>(wanted.size()),
                      "decoding " + std::to_string(wanted.size()) + " channel(s) of " +
                          std::to_string(info.width) + "x" + std::to_string(info.height),
                      path.string());
    FlatImage image(info.width, info.height);
    // HALF decodes to float; the frame buffer converts while decoding, without
    // a second pass.
    Imf::FrameBuffer frame_buffer;
    for (const ChannelSpec& spec : wanted) {
      FlatChannel& channel = image.AddChannel(spec.name, spec.type);
      const bool is_uint = spec.type == PixelType::kUint;
      char* base = is_uint ? reinterpret_cast<char*>(channel.uints.data())
                           : reinterpret_cast<char*>(channel.floats.data());
      const size_t element = is_uint ? sizeof(uint32_t) : sizeof(float);
      frame_buffer.insert(
          spec.name,
          Imf::Slice(is_uint ? Imf::UINT : Imf::FLOAT, base, element, element * info.width));
    }
    file.setFrameBuffer(frame_buffer);
    file.readPixels(0, info.height - 1);
    return image;
  });
}

void WriteFlatExr(const std::filesystem::path& path,
                  const FlatImage& image,
                  const WriteOptions& options) {
  internal::WriteAtomicExr(path, [&](Imf::OStream& stream) {
    Imf::Header header(image.width(), image.height());
    header.compression() = internal::ToImf(options.compression);
    internal::AddCamera(options, &header);
    internal::AddAttributes(options, &header);
    // HALF channels need half-typed storage for the slice.
    std::vector<std::vector<half>> halves;
    halves.reserve(image.channels().size());
    Imf::FrameBuffer frame_buffer;
    for (const FlatChannel& channel : image.channels()) {
      header.channels().insert(channel.name, Imf::Channel(internal::ToImf(channel.type)));
      char* base = nullptr;
      size_t element = 4;
      if (channel.type == PixelType::kUint) {
        base = reinterpret_cast<char*>(const_cast<uint32_t*>(channel.uints.data()));
      } else if (channel.type == PixelType::kFloat) {
        base = reinterpret_cast<char*>(const_cast<float*>(channel.floats.data()));
      } else {
        halves.emplace_back(channel.floats.begin(), channel.floats.end());
        base = reinterpret_cast<char*>(halves.back().data());
        element = sizeof(half);
      }
      frame_buffer.insert(
          channel.name,
          Imf::Slice(internal::ToImf(channel.type), base, element, element * image.width()));
    }
    {
      Imf::OutputFile file(stream, header);
      file.setFrameBuffer(frame_buffer);
      file.writePixels(image.height());
    }
  });
}

}  // namespace lsds::exr
