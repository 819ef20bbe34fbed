#include "libs/exr/exr_info.h"

#include <ImfChannelList.h>
#include <ImfMultiPartInputFile.h>
#include <ImfPartType.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>

#include <algorithm>

#include "libs/exr/exr_internal.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"

namespace lsds::exr {

const char* PixelTypeName(PixelType type) {
  switch (type) {
    case PixelType::kUint:
      return "uint";
    case PixelType::kHalf:
      return "half";
    case PixelType::kFloat:
      return "float";
  }
  return "?";
}

bool ParsePixelType(const std::string& name, PixelType* type) {
  for (PixelType t : {PixelType::kUint, PixelType::kHalf, PixelType::kFloat}) {
    if (name == PixelTypeName(t)) {
      *type = t;
      return true;
    }
  }
  return false;
}

const char* CompressionName(Compression compression) {
  switch (compression) {
    case Compression::kNone:
      return "none";
    case Compression::kRle:
      return "rle";
    case Compression::kZips:
      return "zips";
    case Compression::kZip:
      return "zip";
    case Compression::kPiz:
      return "piz";
  }
  return "?";
}

bool ParseCompression(const std::string& name, Compression* compression) {
  for (Compression c : {Compression::kNone,
                        Compression::kRle,
                        Compression::kZips,
                        Compression::kZip,
                        Compression::kPiz}) {
    if (name == CompressionName(c)) {
      *compression = c;
      return true;
    }
  }
  return false;
}

const ChannelSpec* ExrInfo::Find(const std::string& name) const {
  for (const ChannelSpec& channel : channels) {
    if (channel.name == name) return &channel;
  }
  return nullptr;
}

namespace internal {

Imf::PixelType ToImf(PixelType type) {
  switch (type) {
    case PixelType::kUint:
      return Imf::UINT;
    case PixelType::kHalf:
      return Imf::HALF;
    case PixelType::kFloat:
      return Imf::FLOAT;
  }
  return Imf::FLOAT;
}

Imf::Compression ToImf(Compression compression) {
  switch (compression) {
    case Compression::kNone:
      return Imf::NO_COMPRESSION;
    case Compression::kRle:
      return Imf::RLE_COMPRESSION;
    case Compression::kZips:
      return Imf::ZIPS_COMPRESSION;
    case Compression::kZip:
      return Imf::ZIP_COMPRESSION;
    case Compression::kPiz:
      return Imf::PIZ_COMPRESSION;
  }
  return Imf::ZIP_COMPRESSION;
}

static Imath::M44f ToImath(const Eigen::Matrix4d& m) {
  Imath::M44f out;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) out[r][c] = static_cast<float>(m(c, r));  // row-vector convention
  }
  return out;
}

static Eigen::Matrix4d FromImath(const Imath::M44f& m) {
  Eigen::Matrix4d out;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) out(c, r) = m[r][c];
  }
  return out;
}

void AddCamera(const WriteOptions& options, Imf::Header* header) {
  if (!options.camera) return;
  Imf::addWorldToCamera(*header, ToImath(options.camera->cam_from_world));
  Imf::addWorldToNDC(*header, ToImath(options.camera->ndc_from_world));
}

void AddAttributes(const WriteOptions& options, Imf::Header* header) {
  for (const auto& [name, value] : options.attributes) {
    header->insert(name, Imf::StringAttribute(value));
  }
}

ExrInfo InfoFromHeader(const Imf::Header& header) {
  ExrInfo info;
  const Imath::Box2i& window = header.dataWindow();
  info.width = window.max.x - window.min.x + 1;
  info.height = window.max.y - window.min.y + 1;
  info.deep = header.hasType() && Imf::isDeepData(header.type());
  for (auto it = header.begin(); it != header.end(); ++it) {
    if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) {
      info.attributes[it.name()] = text->value();
    }
  }
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
    PixelType type = PixelType::kFloat;
    if (it.channel().type == Imf::UINT) type = PixelType::kUint;
    if (it.channel().type == Imf::HALF) type = PixelType::kHalf;
    info.channels.push_back({it.name(), type});
  }
  switch (header.compression()) {
    case Imf::NO_COMPRESSION:
      info.compression = Compression::kNone;
      break;
    case Imf::RLE_COMPRESSION:
      info.compression = Compression::kRle;
      break;
    case Imf::ZIPS_COMPRESSION:
      info.compression = Compression::kZips;
      break;
    case Imf::ZIP_COMPRESSION:
      info.compression = Compression::kZip;
      break;
    case Imf::PIZ_COMPRESSION:
      info.compression = Compression::kPiz;
      break;
    default:
      info.compression = Compression::kNone;
      break;  // lossy or exotic: reported by validators
  }
  if (Imf::hasWorldToCamera(header) && Imf::hasWorldToNDC(header)) {
    info.camera =
        HeaderCamera{FromImath(Imf::worldToCamera(header)), FromImath(Imf::worldToNDC(header))};
  }
  return info;
}

void CheckLimits(const std::filesystem::path& path,
                 const Imf::Header& header,
                 const ReadLimits& limits) {
  const Imath::Box2i& window = header.dataWindow();
  const int64_t width = int64_t{window.max.x} - window.min.x + 1;
  const int64_t height = int64_t{window.max.y} - window.min.y + 1;
  const Location where{path.string()};
  if (width <= 0 || height <= 0) throw Error("empty or inverted data window", where);
  if (window.min.x != 0 || window.min.y != 0) {
    throw Error("data window must start at (0, 0), starts at (" + std::to_string(window.min.x) +
                    ", " + std::to_string(window.min.y) + ")",
                where);
  }
  if (width > limits.max_width || height > limits.max_height ||
      width * height > limits.max_pixels) {
    throw Error("image of " + std::to_string(width) + "x" + std::to_string(height) +
                    " pixels exceeds the reader's size limits",
                where);
  }
  int channels = 0;
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) ++channels;
  if (channels > limits.max_channels) {
    throw Error(std::to_string(channels) + " channels exceed the limit of " +
                    std::to_string(limits.max_channels),
                where);
  }
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
    if (it.channel().xSampling != 1 || it.channel().ySampling != 1) {
      throw Error(std::string("channel '") + it.name() + "' is subsampled; lsds layers are not",
                  where);
    }
  }
}

}  // namespace internal

void CheckExrHeader(const std::filesystem::path& path, const ReadLimits& limits) {
  internal::GuardExr(path, [&] {
    RequireRegularFile(path, "EXR file");
    internal::ScanHeader(path, limits);
    return 0;
  });
}

ExrInfo ReadExrInfo(const std::filesystem::path& path, const ReadLimits& limits) {
  return internal::GuardExr(path, [&] {
    RequireRegularFile(path, "layer file");
    internal::ScanHeader(path, limits);
    Imf::MultiPartInputFile file(path.c_str(), 0);  // no threads for a header
    if (file.parts() != 1)
      throw Error("multi-part EXR files are not lsds layers", Location(path.string()));
    const Imf::Header& header = file.header(0);
    if (header.hasTileDescription())
      throw Error("tiled EXR files are not lsds layers", Location(path.string()));
    internal::CheckLimits(path, header, limits);
    return internal::InfoFromHeader(header);
  });
}

}  // namespace lsds::exr
