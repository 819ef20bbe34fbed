#include "libs/collection/bundle_layout.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>

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

uint32_t Bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// Sample k's position inside pixel (x, y) exactly as the generator stores it.
void PositionsOf(const SamplerSettings& sampler,
                 int64_t frame,
                 int x,
                 int y,
                 Eigen::Vector2d* scratch,
                 float* sx,
                 float* sy) {
  PixelSamples(sampler, frame, x, y, scratch);
  for (int k = 0; k < sampler.spp; ++k) {
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
  std::atomic<bool> ok{true};
  tbb::parallel_for(0, full.height(), [&](int y) {
    std::vector<Eigen::Vector2d> scratch(spp);
    std::vector<float> px(spp), py(spp);
    for (int x = 0; x < full.width() && ok.load(std::memory_order_relaxed); ++x) {
      PositionsOf(sampling.sampler, sampling.frame, x, y, scratch.data(), px.data(), py.data());
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
    throw Error(std::string("compact bundle has no header attribute '") + name + "'",
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
    throw Error(std::string("compact bundle header attribute '") + name + "' = '" + text +
                    "' is not a number",
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
      throw Error(std::string("compact bundle header attribute '") + kClassTableAttribute +
                      "': entry '" + entry + "' is not 'instance:class'",
                  Location(path.string()));
    }
  }
  return table;
}

bool IsCompact(const exr::ExrInfo& info) {
  const auto it = info.attributes.find(kBundleLayoutAttribute);
  return it != info.attributes.end() && it->second == "compact";
}

}  // namespace

const char* BundleLayoutName(BundleLayout layout) {
  return layout == BundleLayout::kCompact ? "compact" : "full";
}

bool ParseBundleLayout(const std::string& name, BundleLayout* layout) {
  if (name == "full") {
    *layout = BundleLayout::kFull;
  } else if (name == "compact") {
    *layout = BundleLayout::kCompact;
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
  bool compact = layout == BundleLayout::kCompact && sampling.has_value();
  const int spp = compact ? sampling->sampler.spp : 0;
  for (const exr::ChannelSpec& spec : FullBundleChannels()) {
    const DeepChannel* c = full.Find(spec.name);
    compact = compact && c != nullptr && c->type == spec.type;
  }
  if (compact) {
    for (uint32_t n : full.sample_counts()) {
      if (n != static_cast<uint32_t>(spp)) {
        compact = false;
        break;
      }
    }
  }
  // Positions that are not the rule's must be stored; then nothing collapses.
  if (compact) compact = PositionsDerivable(full, *sampling);
  if (!compact) {
    exr::WriteDeepExr(path, full, options);
    return;
  }

  const uint32_t* inst = full.Get("instanceid").uints.data();
  const uint32_t* cls = full.Get("classid").uints.data();
  const float* value[4] = {full.Get("Z").floats.data(),
                           full.Get("NX").floats.data(),
                           full.Get("NY").floats.data(),
                           full.Get("NZ").floats.data()};
  // The class of each instance, if the frame has one.
  std::map<uint32_t, uint32_t> class_of;
  bool class_is_function = true;
  {
    uint32_t last_instance = 0, last_class = 0;
    bool have_last = false;
    for (uint64_t s = 0; s < full.total_samples() && class_is_function; ++s) {
      if (have_last && inst[s] == last_instance && cls[s] == last_class) continue;
      const auto [it, inserted] = class_of.emplace(inst[s], cls[s]);
      if (!inserted && it->second != cls[s]) class_is_function = false;
      last_instance = inst[s];
      last_class = cls[s];
      have_last = true;
    }
  }
  // A pixel collapses to one sample when all its samples are identical.
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
  DeepImage out(full.width(), full.height(), counts);
  std::vector<std::string> stored = {"instanceid", "Z", "NX", "NY", "NZ"};
  if (!class_is_function) stored.insert(stored.begin() + 1, "classid");
  for (const std::string& name : stored) {
    const DeepChannel& from = full.Get(name);
    DeepChannel& to = out.AddChannel(name, from.type);
    tbb::parallel_for(size_t{0}, full.pixel_count(), [&](size_t p) {
      const uint64_t a = full.offsets()[p], b = out.offsets()[p];
      for (uint32_t k = 0; k < counts[p]; ++k) {
        if (from.type == PixelType::kUint) {
          to.uints[b + k] = from.uints[a + k];
        } else {
          to.floats[b + k] = from.floats[a + k];
        }
      }
    });
  }
  exr::WriteOptions write = options;
  write.attributes[kBundleLayoutAttribute] = "compact";
  write.attributes[kSppAttribute] = std::to_string(spp);
  write.attributes[kSeedAttribute] = std::to_string(sampling->sampler.seed);
  write.attributes[kFrameAttribute] = std::to_string(sampling->frame);
  write.attributes[kJitterAttribute] = FormatDouble(sampling->sampler.jitter);
  if (class_is_function) {
    std::string table;
    for (const auto& [instance, c] : class_of) {
      if (!table.empty()) table += ' ';
      table += std::to_string(instance) + ':' + std::to_string(c);
    }
    write.attributes[kClassTableAttribute] = table;
  }
  exr::WriteDeepExr(path, out, write);
}

std::vector<exr::ChannelSpec> ReadableChannels(const exr::ExrInfo& info) {
  if (!IsCompact(info)) return info.channels;
  std::vector<exr::ChannelSpec> channels = info.channels;
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

DeepImage ReadBundleExr(const fs::path& path,
                        const std::vector<std::string>& channels,
                        const exr::ReadLimits& limits) {
  const exr::ExrInfo info = exr::ReadExrInfo(path, limits);
  if (!IsCompact(info)) return exr::ReadDeepExr(path, channels, limits);
  const Location where(path.string());
  BundleSampling sampling;
  sampling.sampler.spp = ParseAttribute<int>(info, kSppAttribute, path);
  sampling.sampler.seed = ParseAttribute<uint64_t>(info, kSeedAttribute, path);
  sampling.sampler.jitter = ParseAttribute<double>(info, kJitterAttribute, path);
  sampling.frame = ParseAttribute<int64_t>(info, kFrameAttribute, path);
  try {
    CheckSamplerSettings(sampling.sampler);
  } catch (const Error& e) {
    throw Error("compact bundle header: " + e.message(), where);
  }
  const int spp = sampling.sampler.spp;
  const bool class_derived = info.Find("classid") == nullptr;
  const std::map<uint32_t, uint32_t> class_of =
      class_derived ? ParseClassTable(info, path) : std::map<uint32_t, uint32_t>{};

  std::vector<std::string> wanted = channels;
  if (wanted.empty()) {
    for (const exr::ChannelSpec& spec : ReadableChannels(info)) wanted.push_back(spec.name);
  }
  std::vector<std::string> stored;
  auto need = [&](const std::string& name) {
    if (std::find(stored.begin(), stored.end(), name) == stored.end()) stored.push_back(name);
  };
  for (const std::string& name : wanted) {
    if (info.Find(name) != nullptr) {
      need(name);
    } else if (name == "classid" && class_derived) {
      need("instanceid");
    } else if (name != "SX" && name != "SY") {
      throw Error("has no channel '" + name + "'", where);
    }
  }
  const DeepImage packed = exr::ReadDeepExr(path, stored, limits);

  // Every pixel holds spp samples: stored in full, or one standing for all.
  std::vector<uint32_t> counts(packed.pixel_count());
  uint64_t total = 0;
  for (size_t p = 0; p < counts.size(); ++p) {
    const uint32_t n = packed.sample_counts()[p];
    if (n != 1 && n != static_cast<uint32_t>(spp)) {
      throw Error("pixel (" + std::to_string(p % packed.width()) + ", " +
                      std::to_string(p / packed.width()) + ") of a compact bundle stores " +
                      std::to_string(n) + " samples; the layout allows 1 or " + std::to_string(spp),
                  where);
    }
    counts[p] = spp;
    total += spp;
  }
  if (total > static_cast<uint64_t>(limits.max_deep_samples)) {
    throw Error(std::to_string(total) + " deep samples exceed the reader's limit", where);
  }
  DeepImage image(packed.width(), packed.height(), std::move(counts));
  const int width = image.width();
  for (const std::string& name : wanted) {
    if (name == "SX" || name == "SY") {
      DeepChannel& out = image.AddChannel(name, PixelType::kFloat);
      const bool is_x = name == "SX";
      tbb::parallel_for(0, image.height(), [&](int y) {
        std::vector<Eigen::Vector2d> scratch(spp);
        std::vector<float> px(spp), py(spp);
        for (int x = 0; x < width; ++x) {
          PositionsOf(sampling.sampler, sampling.frame, x, y, scratch.data(), px.data(), py.data());
          std::copy_n(is_x ? px.data() : py.data(), spp, &out.floats[image.FirstSample(x, y)]);
        }
      });
      continue;
    }
    const bool derive_class = name == "classid" && class_derived;
    const DeepChannel& from = packed.Get(derive_class ? "instanceid" : name);
    DeepChannel& out = image.AddChannel(name, derive_class ? PixelType::kUint : from.type);
    std::atomic<bool> unknown{false};
    tbb::parallel_for(size_t{0}, image.pixel_count(), [&](size_t p) {
      const uint64_t a = packed.offsets()[p], b = image.offsets()[p];
      const uint32_t n = packed.sample_counts()[p];
      for (int k = 0; k < spp; ++k) {
        const uint64_t s = a + (n == 1 ? 0 : k);
        if (derive_class) {
          const auto it = class_of.find(from.uints[s]);
          if (it == class_of.end()) {
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
    if (unknown) {
      size_t p = 0;  // the first such pixel, for the message
      while (class_of.count(from.uints[packed.offsets()[p]]) != 0 &&
             (packed.sample_counts()[p] == 1 ||
              std::all_of(&from.uints[packed.offsets()[p]],
                          &from.uints[packed.offsets()[p + 1]],
                          [&](uint32_t id) { return class_of.count(id) != 0; }))) {
        ++p;
      }
      throw Error("pixel (" + std::to_string(p % width) + ", " + std::to_string(p / width) +
                      ") holds an instance id missing from the header's '" + kClassTableAttribute +
                      "' table",
                  where);
    }
  }
  return image;
}

}  // namespace lsds
