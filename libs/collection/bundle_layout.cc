#include "libs/collection/bundle_layout.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>

#include "libs/collection/bundle_residual.h"
#include "libs/exr/exr_info.h"
#include "libs/util/error.h"

namespace lsds {

namespace fs = std::filesystem;
using exr::DeepChannel;
using exr::DeepImage;
using exr::PixelType;

namespace {

// Header attributes of a compact bundle (docs/format.md "Pixel bundles").
constexpr const char* kSppAttribute = "lsdsSamplesPerPixel";
constexpr const char* kSeedAttribute = "lsdsSamplingSeed";
constexpr const char* kFrameAttribute = "lsdsSamplingFrame";
constexpr const char* kJitterAttribute = "lsdsSamplingJitter";
constexpr const char* kClassTableAttribute = "lsdsClassOfInstance";
// Residual bundles: the view the depths are predicted with.
constexpr const char* kIntrinsicsAttribute = "lsdsBundleIntrinsics";  // "fx fy cx cy"
constexpr const char* kRotationAttribute = "lsdsBundleRotation";      // cam_from_world, row-major
constexpr const char* kDepthKindAttribute = "lsdsBundleDepthKind";    // planar | perspective

uint32_t Bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// Sample k's position inside pixel (x, y) exactly as the generator stores it.
void PositionsOf(
    const FrameSampler& sampler, int x, int y, Eigen::Vector2d* scratch, float* sx, float* sy) {
  sampler.PixelSamples(x, y, scratch);
  for (int k = 0; k < sampler.spp(); ++k) {
    sx[k] = static_cast<float>(scratch[k].x() - x);
    sy[k] = static_cast<float>(scratch[k].y() - y);
  }
}

// True when the full image's SX/SY are the sampling rule's positions, bit for
// bit.
bool PositionsDerivable(const DeepImage& full, const BundleSampling& sampling) {
  const DeepChannel* sx = full.Find("SX");
  const DeepChannel* sy = full.Find("SY");
  if (sx == nullptr || sy == nullptr) return false;
  const int spp = sampling.sampler.spp;
  const FrameSampler sampler(sampling.sampler, sampling.frame);
  std::atomic<bool> ok{true};
  tbb::parallel_for(0, full.height(), [&](int y) {
    std::vector<Eigen::Vector2d> scratch(spp);
    std::vector<float> px(spp), py(spp);
    for (int x = 0; x < full.width() && ok.load(std::memory_order_relaxed); ++x) {
      PositionsOf(sampler, x, y, scratch.data(), px.data(), py.data());
      const uint64_t first = full.FirstSample(x, y);
      for (int k = 0; k < spp; ++k) {
        if (Bits(sx->floats[first + k]) != Bits(px[k]) ||
            Bits(sy->floats[first + k]) != Bits(py[k])) {
          ok = false;
          return;
        }
      }
    }
  });
  return ok;
}

std::string FormatDouble(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

std::string Attribute(const exr::ExrInfo& info, const char* name, const fs::path& path) {
  const auto it = info.attributes.find(name);
  if (it == info.attributes.end()) {
    throw Error(std::string("bundle has no header attribute '") + name + "'",
                Location(path.string()));
  }
  return it->second;
}

template <typename T>
T ParseAttribute(const exr::ExrInfo& info, const char* name, const fs::path& path) {
  const std::string text = Attribute(info, name, path);
  std::istringstream in(text);
  T value{};
  in >> value;
  if (!in || !in.eof()) {
    throw Error(
        std::string("bundle header attribute '") + name + "' = '" + text + "' is not a number",
        Location(path.string()));
  }
  return value;
}

std::map<uint32_t, uint32_t> ParseClassTable(const exr::ExrInfo& info, const fs::path& path) {
  std::map<uint32_t, uint32_t> table;
  std::istringstream in(Attribute(info, kClassTableAttribute, path));
  std::string entry;
  while (in >> entry) {
    const size_t colon = entry.find(':');
    try {
      if (colon == std::string::npos) throw std::invalid_argument(entry);
      size_t used_a = 0, used_b = 0;
      const unsigned long long instance = std::stoull(entry.substr(0, colon), &used_a);
      const unsigned long long cls = std::stoull(entry.substr(colon + 1), &used_b);
      if (used_a != colon || used_b != entry.size() - colon - 1 || instance > UINT32_MAX ||
          cls > UINT32_MAX) {
        throw std::invalid_argument(entry);
      }
      table[static_cast<uint32_t>(instance)] = static_cast<uint32_t>(cls);
    } catch (const std::exception&) {
      throw Error(std::string("bundle header attribute '") + kClassTableAttribute + "': entry '" +
                      entry + "' is not 'instance:class'",
                  Location(path.string()));
    }
  }
  return table;
}

// The numbers of a header attribute holding `count` of them, separated by spaces.
std::vector<double> ParseNumbers(const exr::ExrInfo& info,
                                 const char* name,
                                 size_t count,
                                 const fs::path& path) {
  const std::string text = Attribute(info, name, path);
  std::istringstream in(text);
  std::vector<double> numbers;
  double v = 0;
  while (in >> v) numbers.push_back(v);
  if (!in.eof() || numbers.size() != count) {
    throw Error(std::string("bundle header attribute '") + name + "' = '" + text + "' is not " +
                    std::to_string(count) + " numbers",
                Location(path.string()));
  }
  return numbers;
}

void AddViewAttributes(const BundleView& view, std::map<std::string, std::string>* attributes) {
  const PinholeCamera& k = view.intrinsics;
  (*attributes)[kIntrinsicsAttribute] = FormatDouble(k.fx) + ' ' + FormatDouble(k.fy) + ' ' +
                                        FormatDouble(k.cx) + ' ' + FormatDouble(k.cy);
  std::string rotation;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      if (!rotation.empty()) rotation += ' ';
      rotation += FormatDouble(view.cam_from_world_rotation(r, c));
    }
  }
  (*attributes)[kRotationAttribute] = rotation;
  (*attributes)[kDepthKindAttribute] =
      view.depth_kind == DepthKind::kPerspective ? "perspective" : "planar";
}

BundleView ParseViewAttributes(const exr::ExrInfo& info, const fs::path& path) {
  BundleView view;
  const std::vector<double> k = ParseNumbers(info, kIntrinsicsAttribute, 4, path);
  view.intrinsics.width = info.width;
  view.intrinsics.height = info.height;
  view.intrinsics.fx = k[0];
  view.intrinsics.fy = k[1];
  view.intrinsics.cx = k[2];
  view.intrinsics.cy = k[3];
  const std::vector<double> r = ParseNumbers(info, kRotationAttribute, 9, path);
  for (int i = 0; i < 9; ++i) view.cam_from_world_rotation(i / 3, i % 3) = r[i];
  const std::string kind = Attribute(info, kDepthKindAttribute, path);
  if (kind != "planar" && kind != "perspective") {
    throw Error(std::string("bundle header attribute '") + kDepthKindAttribute + "' = '" + kind +
                    "' is not planar or perspective",
                Location(path.string()));
  }
  view.depth_kind = kind == "perspective" ? DepthKind::kPerspective : DepthKind::kPlanar;
  return view;
}

// True when `full` can be stored compact or residual: every channel of the full
// layout with its type, `spp` samples in every pixel, and the sampling rule's
// positions.
bool Derivable(const DeepImage& full, const BundleSampling& sampling) {
  for (const exr::ChannelSpec& spec : FullBundleChannels()) {
    const DeepChannel* c = full.Find(spec.name);
    if (c == nullptr || c->type != spec.type) return false;
  }
  const uint32_t spp = static_cast<uint32_t>(sampling.sampler.spp);
  for (uint32_t n : full.sample_counts()) {
    if (n != spp) return false;
  }
  // Positions that are not the rule's must be stored.
  return PositionsDerivable(full, sampling);
}

// The class of each instance in `full`, or nothing when one instance has two.
std::optional<std::map<uint32_t, uint32_t>> ClassOfInstance(const DeepImage& full) {
  const std::vector<uint32_t>& inst = full.Get("instanceid").uints;
  const std::vector<uint32_t>& cls = full.Get("classid").uints;
  std::map<uint32_t, uint32_t> class_of;
  uint32_t last_instance = 0, last_class = 0;
  bool have_last = false;
  for (uint64_t s = 0; s < full.total_samples(); ++s) {
    if (have_last && inst[s] == last_instance && cls[s] == last_class) continue;
    const auto [it, inserted] = class_of.emplace(inst[s], cls[s]);
    if (!inserted && it->second != cls[s]) return std::nullopt;
    last_instance = inst[s];
    last_class = cls[s];
    have_last = true;
  }
  return class_of;
}

// Fills channel `name` of `band`, rows [first_row, ...) of a file whose
// pixels hold 1 or all of `full`'s samples, from `full`.
void CopyBand(const DeepImage& full, const std::string& name, int first_row, DeepImage* band) {
  const DeepChannel& source = full.Get(name);
  DeepChannel& target = band->Get(name);
  const size_t first_pixel = static_cast<size_t>(first_row) * full.width();
  tbb::parallel_for(size_t{0}, band->pixel_count(), [&](size_t p) {
    const uint64_t a = full.offsets()[first_pixel + p], b = band->offsets()[p];
    const uint32_t n = band->sample_counts()[p];
    if (source.type == PixelType::kUint) {
      std::copy_n(source.uints.begin() + static_cast<ptrdiff_t>(a),
                  n,
                  target.uints.begin() + static_cast<ptrdiff_t>(b));
    } else {
      std::copy_n(source.floats.begin() + static_cast<ptrdiff_t>(a),
                  n,
                  target.floats.begin() + static_cast<ptrdiff_t>(b));
    }
  });
}

// The stored channels' specs: `names` with `full`'s types, `residuals` UINT.
std::vector<exr::ChannelSpec> StoredChannels(const DeepImage& full,
                                             const std::vector<std::string>& names,
                                             const std::vector<std::string>& residuals = {}) {
  std::vector<exr::ChannelSpec> specs;
  specs.reserve(names.size() + residuals.size());
  for (const std::string& name : names) specs.push_back({name, full.Get(name).type});
  for (const std::string& name : residuals) specs.push_back({name, PixelType::kUint});
  return specs;
}

// Compact: a pixel whose samples are all identical keeps one. Written a band
// of rows at a time: the writer never holds a second copy of the bundle.
void WriteCompactSamples(const fs::path& path,
                         const DeepImage& full,
                         int spp,
                         bool store_class,
                         const exr::WriteOptions& write) {
  const uint32_t* inst = full.Get("instanceid").uints.data();
  const uint32_t* cls = full.Get("classid").uints.data();
  const float* value[4] = {full.Get("Z").floats.data(),
                           full.Get("NX").floats.data(),
                           full.Get("NY").floats.data(),
                           full.Get("NZ").floats.data()};
  std::vector<uint32_t> counts(full.pixel_count());
  tbb::parallel_for(size_t{0}, full.pixel_count(), [&](size_t p) {
    const uint64_t first = full.offsets()[p];
    bool same = true;
    for (int k = 1; k < spp && same; ++k) {
      same = inst[first + k] == inst[first] && cls[first + k] == cls[first];
      for (int c = 0; c < 4 && same; ++c) {
        same = Bits(value[c][first + k]) == Bits(value[c][first]);
      }
    }
    counts[p] = same ? 1 : spp;
  });
  std::vector<std::string> stored = {"instanceid", "Z", "NX", "NY", "NZ"};
  if (store_class) stored.insert(stored.begin() + 1, "classid");
  exr::WriteDeepExrInBands(
      path,
      full.width(),
      counts,
      StoredChannels(full, stored),
      [&](int first_row, DeepImage* band) {
        for (const std::string& name : stored) CopyBand(full, name, first_row, band);
      },
      write);
}

// Residual: every sample; depths and normals as residuals of their
// prediction. Written a band of rows at a time, as compact.
void WriteResidualSamples(const fs::path& path,
                          const DeepImage& full,
                          const BundleView& view,
                          int spp,
                          bool store_class,
                          const exr::WriteOptions& write) {
  std::vector<std::string> copied = {"instanceid"};
  if (store_class) copied.push_back("classid");
  const std::vector<std::string> residuals(std::begin(kBundleResidualChannels),
                                           std::end(kBundleResidualChannels));
  const float* value[4];
  for (int c = 0; c < 4; ++c) value[c] = full.Get(kBundleValueChannels[c]).floats.data();
  const float* sx = full.Get("SX").floats.data();
  const float* sy = full.Get("SY").floats.data();
  const PlaneDepthPredictor predictor(view);
  exr::WriteDeepExrInBands(
      path,
      full.width(),
      full.sample_counts(),
      StoredChannels(full, copied, residuals),
      [&](int first_row, DeepImage* band) {
        for (const std::string& name : copied) CopyBand(full, name, first_row, band);
        uint32_t* residual[4];
        for (int c = 0; c < 4; ++c) residual[c] = band->Get(residuals[c]).uints.data();
        tbb::parallel_for(0, band->height(), [&](int r) {
          const int y = first_row + r;
          const uint64_t first = full.FirstSample(0, y), band_first = band->FirstSample(0, r);
          const BundleRow row{y, full.width(), spp, sx + first, sy + first};
          const float* row_value[4];
          uint32_t* row_residual[4];
          for (int c = 0; c < 4; ++c) {
            row_value[c] = value[c] + first;
            row_residual[c] = residual[c] + band_first;
          }
          EncodeBundleRow(predictor, row, row_value, row_residual);
        });
      },
      write);
}

}  // namespace

const char* BundleLayoutName(BundleLayout layout) {
  switch (layout) {
    case BundleLayout::kCompact:
      return "compact";
    case BundleLayout::kResidual:
      return "residual";
    case BundleLayout::kFull:
      break;
  }
  return "full";
}

bool ParseBundleLayout(const std::string& name, BundleLayout* layout) {
  if (name == "full") {
    *layout = BundleLayout::kFull;
  } else if (name == "compact") {
    *layout = BundleLayout::kCompact;
  } else if (name == "residual") {
    *layout = BundleLayout::kResidual;
  } else {
    return false;
  }
  return true;
}

const std::vector<exr::ChannelSpec>& FullBundleChannels() {
  static const std::vector<exr::ChannelSpec> channels = {{"instanceid", PixelType::kUint},
                                                         {"classid", PixelType::kUint},
                                                         {"Z", PixelType::kFloat},
                                                         {"NX", PixelType::kFloat},
                                                         {"NY", PixelType::kFloat},
                                                         {"NZ", PixelType::kFloat},
                                                         {"SX", PixelType::kFloat},
                                                         {"SY", PixelType::kFloat}};
  return channels;
}

void WriteBundleExr(const fs::path& path,
                    const DeepImage& full,
                    BundleLayout layout,
                    const std::optional<BundleSampling>& sampling,
                    const exr::WriteOptions& options) {
  if (layout == BundleLayout::kResidual && !(sampling && sampling->view)) {
    layout = BundleLayout::kCompact;
  }
  if (layout != BundleLayout::kFull && !(sampling && Derivable(full, *sampling))) {
    layout = BundleLayout::kFull;
  }
  if (layout == BundleLayout::kFull) {
    exr::WriteDeepExr(path, full, options);
    return;
  }
  const int spp = sampling->sampler.spp;
  const std::optional<std::map<uint32_t, uint32_t>> class_of = ClassOfInstance(full);
  exr::WriteOptions write = options;
  write.attributes[kBundleLayoutAttribute] = BundleLayoutName(layout);
  write.attributes[kSppAttribute] = std::to_string(spp);
  write.attributes[kSeedAttribute] = std::to_string(sampling->sampler.seed);
  write.attributes[kFrameAttribute] = std::to_string(sampling->frame);
  write.attributes[kJitterAttribute] = FormatDouble(sampling->sampler.jitter);
  if (class_of) {
    std::string table;
    for (const auto& [instance, c] : *class_of) {
      if (!table.empty()) table += ' ';
      table += std::to_string(instance) + ':' + std::to_string(c);
    }
    write.attributes[kClassTableAttribute] = table;
  }
  if (layout == BundleLayout::kCompact) {
    WriteCompactSamples(path, full, spp, !class_of, write);
    return;
  }
  AddViewAttributes(*sampling->view, &write.attributes);
  WriteResidualSamples(path, full, *sampling->view, spp, !class_of, write);
}

BundleLayout BundleLayoutOf(const exr::ExrInfo& info) {
  BundleLayout layout = BundleLayout::kFull;
  const auto it = info.attributes.find(kBundleLayoutAttribute);
  if (it != info.attributes.end()) ParseBundleLayout(it->second, &layout);
  return layout;
}

std::vector<exr::ChannelSpec> ReadableChannels(const exr::ExrInfo& info) {
  const BundleLayout layout = BundleLayoutOf(info);
  if (layout == BundleLayout::kFull) return info.channels;
  std::vector<exr::ChannelSpec> channels;
  for (const exr::ChannelSpec& stored : info.channels) {
    exr::ChannelSpec readable = stored;
    for (int c = 0; c < 4 && layout == BundleLayout::kResidual; ++c) {
      if (stored.name == kBundleResidualChannels[c] && stored.type == PixelType::kUint) {
        readable = {kBundleValueChannels[c], PixelType::kFloat};
      }
    }
    channels.push_back(readable);
  }
  for (const char* derived : {"classid", "SX", "SY"}) {
    if (info.Find(derived) != nullptr) continue;
    if (std::string(derived) == "classid" && info.attributes.count(kClassTableAttribute) == 0) {
      continue;
    }
    channels.push_back(
        {derived, std::string(derived) == "classid" ? PixelType::kUint : PixelType::kFloat});
  }
  std::sort(channels.begin(), channels.end(), [](const auto& a, const auto& b) {
    return a.name < b.name;
  });
  return channels;
}

namespace {

// The stored residual channel of value channel `name` ("Z" -> 0), or -1.
int ResidualIndex(const std::string& name) {
  for (int c = 0; c < 4; ++c) {
    if (name == kBundleValueChannels[c]) return c;
  }
  return -1;
}

// Sample positions of row y (all pixels, spp each) by the sampling rule.
void RowPositions(const FrameSampler& sampler,
                  int y,
                  int width,
                  std::vector<Eigen::Vector2d>* scratch,
                  float* sx,
                  float* sy) {
  const int spp = sampler.spp();
  for (int x = 0; x < width; ++x) {
    PositionsOf(sampler,
                x,
                y,
                scratch->data(),
                sx + static_cast<size_t>(x) * spp,
                sy + static_cast<size_t>(x) * spp);
  }
}

// The stages of ReadBundleExr: read the sampling from the header, choose the stored channels
// to decode, expand every pixel to spp samples, decode the residual values, then fill each
// wanted channel (positions from the sampling rule, decoded values, stored channels and the
// class ids derived from the instance ids).

// The sampling rule a compact or residual bundle's header records.
BundleSampling ReadSampling(const exr::ExrInfo& info, const fs::path& path, bool residual) {
  BundleSampling sampling;
  sampling.sampler.spp = ParseAttribute<int>(info, kSppAttribute, path);
  sampling.sampler.seed = ParseAttribute<uint64_t>(info, kSeedAttribute, path);
  sampling.sampler.jitter = ParseAttribute<double>(info, kJitterAttribute, path);
  sampling.frame = ParseAttribute<int64_t>(info, kFrameAttribute, path);
  try {
    CheckSamplerSettings(sampling.sampler);
  } catch (const Error& e) {
    throw Error("bundle header: " + e.message(), Location(path.string()));
  }
  if (residual) sampling.view = ParseViewAttributes(info, path);
  return sampling;
}

// The stored channels to read for the wanted ones, and which residual values to decode.
struct DecodePlan {
  std::vector<std::string> names;
  bool decode[4] = {false, false, false, false};
  bool any_decoded() const { return decode[0] || decode[1] || decode[2] || decode[3]; }
};

DecodePlan PlanDecode(const exr::ExrInfo& info,
                      const std::vector<std::string>& wanted,
                      bool residual,
                      bool class_derived,
                      const Location& where) {
  DecodePlan stored;
  auto need = [&](const std::string& name) {
    if (std::find(stored.names.begin(), stored.names.end(), name) == stored.names.end())
      stored.names.push_back(name);
  };
  // Residual depths and normals: which values to decode (the depth needs the
  // normals).
  for (const std::string& name : wanted) {
    const int c = residual ? ResidualIndex(name) : -1;
    if (c >= 0) {
      const exr::ChannelSpec* spec = info.Find(kBundleResidualChannels[c]);
      if (spec == nullptr || spec->type != PixelType::kUint) {
        throw Error(std::string("residual bundle has no uint channel '") +
                        kBundleResidualChannels[c] + "' (for " + name + ")",
                    where);
      }
      stored.decode[c] = true;
      if (c == 0) stored.decode[1] = stored.decode[2] = stored.decode[3] = true;
    } else if (info.Find(name) != nullptr) {
      need(name);
    } else if (name == "classid" && class_derived) {
      need("instanceid");
    } else if (name != "SX" && name != "SY") {
      throw Error("has no channel '" + name + "'", where);
    }
  }
  for (int c = 0; c < 4; ++c) {
    if (!stored.decode[c]) continue;
    if (info.Find(kBundleResidualChannels[c]) == nullptr) {
      throw Error(std::string("residual bundle has no channel '") + kBundleResidualChannels[c] +
                      "' (the depth's prediction needs every normal)",
                  where);
    }
    need(kBundleResidualChannels[c]);
  }
  return stored;
}

// An image of the packed one's size with spp samples per pixel. Every pixel holds spp
// samples: stored in full, or (compact) one standing for all.
DeepImage ExpandedImage(const DeepImage& packed,
                        int spp,
                        BundleLayout layout,
                        const exr::ReadLimits& limits,
                        const Location& where) {
  const bool residual = layout == BundleLayout::kResidual;
  std::vector<uint32_t> counts(packed.pixel_count());
  uint64_t total = 0;
  for (size_t p = 0; p < counts.size(); ++p) {
    const uint32_t n = packed.sample_counts()[p];
    if (n != static_cast<uint32_t>(spp) && (residual || n != 1)) {
      throw Error("pixel (" + std::to_string(p % packed.width()) + ", " +
                      std::to_string(p / packed.width()) + ") of a " + BundleLayoutName(layout) +
                      " bundle stores " + std::to_string(n) + " samples; the layout allows " +
                      (residual ? "" : "1 or ") + std::to_string(spp),
                  where);
    }
    counts[p] = spp;
    total += spp;
  }
  if (total > static_cast<uint64_t>(limits.max_deep_samples)) {
    throw Error(std::to_string(total) + " deep samples exceed the reader's limit", where);
  }
  return DeepImage(packed.width(), packed.height(), std::move(counts));
}

// Residual values decode into scratch arrays (the normals a depth needs may
// not be wanted), which then move into the image.
void DecodeResiduals(const DeepImage& packed,
                     const DeepImage& image,
                     const FrameSampler& sampler,
                     const BundleView& view,
                     const DecodePlan& stored,
                     std::vector<float> (&decoded)[4]) {
  const int width = image.width();
  const int spp = sampler.spp();
  const uint32_t* residual_of[4] = {};
  float* value_of[4] = {};
  for (int c = 0; c < 4; ++c) {
    if (!stored.decode[c]) continue;
    residual_of[c] = packed.Get(kBundleResidualChannels[c]).uints.data();
    decoded[c].resize(image.total_samples());
    value_of[c] = decoded[c].data();
  }
  const PlaneDepthPredictor predictor(view);
  tbb::parallel_for(0, image.height(), [&](int y) {
    const size_t row_samples = static_cast<size_t>(width) * spp;
    std::vector<Eigen::Vector2d> scratch(spp);
    std::vector<float> sx(row_samples), sy(row_samples);
    RowPositions(sampler, y, width, &scratch, sx.data(), sy.data());
    const uint64_t first = image.FirstSample(0, y);
    const BundleRow row{y, width, spp, sx.data(), sy.data()};
    const uint32_t* row_residual[4];
    float* row_value[4];
    for (int c = 0; c < 4; ++c) {
      row_residual[c] = residual_of[c] ? residual_of[c] + first : nullptr;
      row_value[c] = value_of[c] ? value_of[c] + first : nullptr;
    }
    DecodeBundleRow(predictor, row, row_residual, row_value);
  });
}

// SX or SY: the sample positions, by the sampling rule.
void AddPositionChannel(const std::string& name, const FrameSampler& sampler, DeepImage* image) {
  const int width = image->width();
  const int spp = sampler.spp();
  DeepChannel& out = image->AddChannel(name, PixelType::kFloat);
  const bool is_x = name == "SX";
  tbb::parallel_for(0, image->height(), [&](int y) {
    std::vector<Eigen::Vector2d> scratch(spp);
    std::vector<float> px(spp), py(spp);
    for (int x = 0; x < width; ++x) {
      PositionsOf(sampler, x, y, scratch.data(), px.data(), py.data());
      std::copy_n(is_x ? px.data() : py.data(), spp, &out.floats[image->FirstSample(x, y)]);
    }
  });
}

// A stored channel spread to spp samples per pixel, or (`class_of` given) the class ids of
// the stored instance ids.
void AddStoredChannel(const std::string& name,
                      const DeepImage& packed,
                      int spp,
                      const std::map<uint32_t, uint32_t>* class_of,
                      const Location& where,
                      DeepImage* image) {
  const bool derive_class = class_of != nullptr;
  const DeepChannel& from = packed.Get(derive_class ? "instanceid" : name);
  DeepChannel& out = image->AddChannel(name, derive_class ? PixelType::kUint : from.type);
  std::atomic<bool> unknown{false};
  tbb::parallel_for(size_t{0}, image->pixel_count(), [&](size_t p) {
    const uint64_t a = packed.offsets()[p], b = image->offsets()[p];
    const uint32_t n = packed.sample_counts()[p];
    for (int k = 0; k < spp; ++k) {
      const uint64_t s = a + (n == 1 ? 0 : k);
      if (derive_class) {
        const auto it = class_of->find(from.uints[s]);
        if (it == class_of->end()) {
          unknown = true;
          return;
        }
        out.uints[b + k] = it->second;
      } else if (from.type == PixelType::kUint) {
        out.uints[b + k] = from.uints[s];
      } else {
        out.floats[b + k] = from.floats[s];
      }
    }
  });
  if (!unknown) return;
  size_t p = 0;  // the first such pixel, for the message
  while (class_of->count(from.uints[packed.offsets()[p]]) != 0 &&
         (packed.sample_counts()[p] == 1 ||
          std::all_of(&from.uints[packed.offsets()[p]],
                      &from.uints[packed.offsets()[p + 1]],
                      [&](uint32_t id) { return class_of->count(id) != 0; }))) {
    ++p;
  }
  const int width = image->width();
  throw Error("pixel (" + std::to_string(p % width) + ", " + std::to_string(p / width) +
                  ") holds an instance id missing from the header's '" + kClassTableAttribute +
                  "' table",
              where);
}

}  // namespace

DeepImage ReadBundleExr(const fs::path& path,
                        const std::vector<std::string>& channels,
                        const exr::ReadLimits& limits) {
  const exr::ExrInfo info = exr::ReadExrInfo(path, limits);
  const BundleLayout layout = BundleLayoutOf(info);
  if (layout == BundleLayout::kFull) return exr::ReadDeepExr(path, channels, limits);
  const bool residual = layout == BundleLayout::kResidual;
  const Location where(path.string());
  const BundleSampling sampling = ReadSampling(info, path, residual);
  const int spp = sampling.sampler.spp;
  const FrameSampler sampler(sampling.sampler, sampling.frame);
  const bool class_derived = info.Find("classid") == nullptr;
  const std::map<uint32_t, uint32_t> class_of =
      class_derived ? ParseClassTable(info, path) : std::map<uint32_t, uint32_t>{};

  std::vector<std::string> wanted = channels;
  if (wanted.empty()) {
    for (const exr::ChannelSpec& spec : ReadableChannels(info)) wanted.push_back(spec.name);
  }
  const DecodePlan stored = PlanDecode(info, wanted, residual, class_derived, where);
  const DeepImage packed = exr::ReadDeepExr(path, stored.names, limits);
  DeepImage image = ExpandedImage(packed, spp, layout, limits, where);
  std::vector<float> decoded[4];
  if (stored.any_decoded())
    DecodeResiduals(packed, image, sampler, *sampling.view, stored, decoded);
  for (const std::string& name : wanted) {
    if (name == "SX" || name == "SY") {
      AddPositionChannel(name, sampler, &image);
      continue;
    }
    const int c = residual ? ResidualIndex(name) : -1;
    if (c >= 0) {
      image.AddChannel(name, PixelType::kFloat).floats = std::move(decoded[c]);
      continue;
    }
    const bool derive_class = name == "classid" && class_derived;
    AddStoredChannel(name, packed, spp, derive_class ? &class_of : nullptr, where, &image);
  }
  return image;
}

}  // namespace lsds
