// Types shared by the flat and deep EXR readers and writers.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace lsds::exr {

enum class PixelType { kUint, kHalf, kFloat };
const char* PixelTypeName(PixelType type);  // "uint" | "half" | "float", as in docs/format.md
bool ParsePixelType(const std::string& name, PixelType* type);

// Lossless compressions only: truth layers must survive a round trip bit for
// bit.
enum class Compression { kNone, kRle, kZips, kZip, kPiz };
const char* CompressionName(Compression compression);
bool ParseCompression(const std::string& name, Compression* compression);

struct ChannelSpec {
  std::string name;
  PixelType type = PixelType::kFloat;
  bool operator==(const ChannelSpec& o) const { return name == o.name && type == o.type; }
};

// Limits checked on the header before anything is decoded, so that a hostile or
// corrupt file cannot make a reader allocate without bound.
struct ReadLimits {
  int64_t max_width = 1 << 15;
  int64_t max_height = 1 << 15;
  int64_t max_pixels = int64_t{1} << 28;
  int max_channels = 64;
  int64_t max_deep_samples = int64_t{1} << 30;  // in all pixels together
  int max_samples_per_pixel = 1 << 12;
};

// Camera matrices written into EXR headers as the standard attributes
// `worldToCamera` and `worldToNDC`, in Imath's row-vector convention (p' = p *
// M, i.e. the transpose of our matrices).
struct HeaderCamera {
  Eigen::Matrix4d cam_from_world = Eigen::Matrix4d::Identity();  // OpenCV camera frame
  Eigen::Matrix4d ndc_from_world = Eigen::Matrix4d::Identity();  // see docs/format.md
};

struct WriteOptions {
  Compression compression = Compression::kZip;
  std::optional<HeaderCamera> camera;
  // Extra string attributes for the header (e.g. the compact bundle layout's
  // sampling parameters, docs/format.md "Pixel bundles").
  std::map<std::string, std::string> attributes;
};

struct ExrInfo {
  int width = 0;
  int height = 0;
  bool deep = false;
  std::vector<ChannelSpec> channels;  // sorted by name, as EXR stores them
  Compression compression = Compression::kNone;
  std::optional<HeaderCamera> camera;
  std::map<std::string, std::string> attributes;  // the header's string attributes

  const ChannelSpec* Find(const std::string& name) const;
};

}  // namespace lsds::exr
