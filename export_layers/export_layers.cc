#include "export_layers/export_layers.h"

#include "libs/collection/rig.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>
#include <optional>
#include <thread>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "export_layers/png16_encoding.h"
#include "libs/collection/collection_guard.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/imaging/image_codecs.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/npy.h"
#include "libs/util/progress.h"
#include "libs/util/strings.h"

namespace lsds::layer_export {

namespace fs = std::filesystem;

Target ParseTarget(const std::string& name) {
  if (name == "npy") return Target::kNpy;
  if (name == "png16") return Target::kPng16;
  if (name == "tiff") return Target::kTiff;
  throw Error("--to: unknown target '" + name + "'" + DidYouMean(name, {"npy", "png16", "tiff"}) +
              " (npy, png16 or tiff)");
}

const char* TargetName(Target target) {
  switch (target) {
    case Target::kNpy:
      return "npy";
    case Target::kPng16:
      return "png16";
    case Target::kTiff:
      return "tiff";
  }
  return "?";
}

namespace {

struct LayerPlan {
  const LayerInfo* info = nullptr;
  bool integer = false;  // UINT channels (ids)
  std::optional<Png16Encoding> png16;
  LayerSummary summary;  // guarded by the run's mutex
};

const char* Extension(Target target) {
  switch (target) {
    case Target::kNpy:
      return ".npy";
    case Target::kPng16:
      return ".png";
    case Target::kTiff:
      return ".tiff";
  }
  return "";
}

// File of one frame: "000007.npy" (all channels), "000007.png" (one channel)
// or "000007.X.png" (channel X of a multi-channel layer, for PNG and TIFF).
std::string FileName(const std::string& stem,
                     const LayerInfo& layer,
                     size_t channel,
                     Target target) {
  if (target == Target::kNpy || layer.channels.size() == 1) return stem + Extension(target);
  return stem + "." + layer.channels[channel].name + Extension(target);
}

// Whether every channel is UINT (ids) or every one HALF/FLOAT; mixed layers
// cannot be one array.
bool IntegerLayer(const LayerInfo& layer, const std::string& where) {
  bool any_uint = false, any_float = false;
  for (const LayerChannel& c : layer.channels)
    (c.type == exr::PixelType::kUint ? any_uint : any_float) = true;
  if (any_uint && any_float) {
    throw Error("layer '" + layer.name +
                    "' mixes UINT and float channels; export its channels "
                    "one layer at a time is not supported",
                Location(where, "/layers"));
  }
  return any_uint;
}

std::vector<LayerPlan> PlanLayers(const CollectionHeader& header,
                                  const ExportOptions& options,
                                  const std::string& collection_file) {
  std::vector<std::string> names;
  for (const LayerInfo& l : header.layers) names.push_back(l.name);
  std::vector<LayerPlan> plans;
  auto add = [&](const LayerInfo& info) {
    LayerPlan plan;
    plan.info = &info;
    plan.integer = IntegerLayer(info, collection_file);
    plan.summary.name = info.name;
    if (options.target == Target::kPng16)
      plan.png16 = Png16EncodingOf(info.semantic, options.depth_step);
    plans.push_back(plan);
  };
  if (options.layers.empty()) {
    for (const LayerInfo& info : header.layers) {
      if (info.deep || info.channels.empty()) continue;
      if (options.target == Target::kPng16 && !Png16EncodingOf(info.semantic, options.depth_step))
        continue;
      add(info);
    }
    if (plans.empty()) {
      throw Error(std::string("the collection has no flat layer that ") +
                      TargetName(options.target) + " can hold (layers: " + Join(names, ", ") + ")",
                  Location(collection_file, "/layers"));
    }
    return plans;
  }
  for (const std::string& name : options.layers) {
    const LayerInfo* info = header.FindLayer(name);
    if (info == nullptr) {
      throw Error("--layers: the collection has no layer '" + name + "'" + DidYouMean(name, names) +
                      " (layers: " + Join(names, ", ") + ")",
                  Location(collection_file, "/layers"));
    }
    for (const LayerPlan& p : plans)
      if (p.info == info) throw Error("--layers: '" + name + "' given twice");
    if (info->deep) {
      throw Error("--layers: '" + name +
                  "' is a deep layer (several samples per pixel); read it with "
                  "OpenEXR's deep API (docs/format.md, \"Pixel bundles\")");
    }
    if (options.target == Target::kPng16 && !Png16EncodingOf(info->semantic, options.depth_step)) {
      const std::string semantic = info->semantic == name ? "" : " (" + info->semantic + ")";
      throw Error("--layers: '" + name + "'" + semantic +
                  " has no 16-bit PNG encoding: its values are unbounded or "
                  "of unknown range; use --to npy or --to tiff (exact float32)");
    }
    add(*info);
  }
  return plans;
}

// Why a depth cannot be stored at this step, and the step that would store it.
std::string BeyondRangeMessage(const LayerInfo& layer, const Png16Encoding& encoding, float value) {
  return layer.name + " " + FormatNumber(value) +
         " is beyond the 16-bit PNG range of --depth-step " + FormatNumber(encoding.scale) +
         " (up to " + FormatNumber(65535 * encoding.scale) + "); use --depth-step " +
         FormatNumber(Png16StepFor(value)) + " or more, or --clamp-depth to clamp it";
}

// One frame of one layer into the temporary output folder.
class FrameWriter {
 public:
  FrameWriter(const ExportOptions& options, const fs::path& root)
      : options_(options), root_(root) {}

  // Returns the bytes written; counts invalid/clamped pixels into `counts`. Stages: decode the
  // layer and check its channels' types, then write one .npy (channels interleaved) or one
  // TIFF or 16-bit PNG per channel.
  int64_t Write(const CollectionReader& reader,
                const Frame& frame,
                const LayerPlan& plan,
                LayerSummary* counts) const {
    const LayerInfo& layer = *plan.info;
    const fs::path source = reader.LayerPath(frame, layer.name);
    std::vector<std::string> channels;
    for (const LayerChannel& c : layer.channels) channels.push_back(c.name);
    // Through the reader: a residual worldposition layer decodes to X, Y, Z.
    const exr::FlatImage image = reader.ReadFlatLayer(frame, layer.name, channels);
    const size_t n = image.pixel_count();
    std::vector<const exr::FlatChannel*> data;
    for (const std::string& name : channels) {
      const exr::FlatChannel& c = image.Get(name);
      const size_t stored = plan.integer ? c.uints.size() : c.floats.size();
      if (stored != n) {
        throw Error("channel '" + name + "' is not of the declared type " +
                        exr::PixelTypeName(layer.FindChannel(name)->type),
                    Location(source.string()));
      }
      data.push_back(&c);
    }
    const std::string stem = FrameFileStem(frame);  // "000004_left" in a rig
    const fs::path folder = root_ / layer.name;
    if (options_.target == Target::kNpy) {
      const fs::path path = folder / FileName(stem, layer, 0, Target::kNpy);
      WriteNpyLayer(image, data, plan, path, counts);
      return FileSize(path);
    }
    int64_t bytes = 0;
    for (size_t c = 0; c < data.size(); ++c) {
      const fs::path path = folder / FileName(stem, layer, c, options_.target);
      const cv::Mat mat = options_.target == Target::kTiff
                              ? TiffMat(image, *data[c], plan, counts)
                              : Png16Mat(image, *data[c], plan, source, frame.index, counts);
      if (!imaging::ImWrite(path.string(), mat))
        throw Error("OpenCV could not write the file", Location(path.string()));
      bytes += FileSize(path);
    }
    return bytes;
  }

 private:
  static int64_t FileSize(const fs::path& path) {
    std::error_code ec;
    return static_cast<int64_t>(fs::file_size(path, ec));
  }

  // Channels interleaved, as numpy's (height, width, channels).
  static void WriteNpyLayer(const exr::FlatImage& image,
                            const std::vector<const exr::FlatChannel*>& data,
                            const LayerPlan& plan,
                            const fs::path& path,
                            LayerSummary* counts) {
    const size_t n = image.pixel_count();
    const size_t c_count = data.size();
    std::vector<int64_t> shape = {image.height(), image.width()};
    if (c_count > 1) shape.push_back(static_cast<int64_t>(c_count));
    if (plan.integer) {
      std::vector<uint32_t> out(n * c_count);
      for (size_t c = 0; c < c_count; ++c)
        for (size_t p = 0; p < n; ++p) out[p * c_count + c] = data[c]->uints[p];
      WriteNpy(path,
               "'<u4'",
               shape,
               std::string(reinterpret_cast<const char*>(out.data()), out.size() * 4));
    } else {
      std::vector<float> out(n * c_count);
      for (size_t c = 0; c < c_count; ++c)
        for (size_t p = 0; p < n; ++p) out[p * c_count + c] = data[c]->floats[p];
      for (float v : out)
        if (!std::isfinite(v)) ++counts->invalid_pixels;
      WriteNpy(path,
               "'<f4'",
               shape,
               std::string(reinterpret_cast<const char*>(out.data()), out.size() * 4));
    }
  }

  // OpenCV has no 32-bit unsigned type: ids go as int32 with the same
  // bits (exact; numpy: .view(np.uint32)).
  static cv::Mat TiffMat(const exr::FlatImage& image,
                         const exr::FlatChannel& channel,
                         const LayerPlan& plan,
                         LayerSummary* counts) {
    const size_t n = image.pixel_count();
    cv::Mat mat(image.height(), image.width(), plan.integer ? CV_32SC1 : CV_32FC1);
    if (plan.integer) {
      std::memcpy(mat.data, channel.uints.data(), n * 4);
    } else {
      std::memcpy(mat.data, channel.floats.data(), n * 4);
      for (float v : channel.floats)
        if (!std::isfinite(v)) ++counts->invalid_pixels;
    }
    return mat;
  }

  // Ids as they are (at most 65535); floats by the layer's 16-bit encoding, out-of-range
  // depths an error unless --clamp-depth.
  cv::Mat Png16Mat(const exr::FlatImage& image,
                   const exr::FlatChannel& channel,
                   const LayerPlan& plan,
                   const fs::path& source,
                   int64_t frame_index,
                   LayerSummary* counts) const {
    const LayerInfo& layer = *plan.info;
    const int w = image.width(), h = image.height();
    const size_t n = image.pixel_count();
    cv::Mat mat(h, w, CV_16UC1);
    uint16_t* out = mat.ptr<uint16_t>();
    const Png16Encoding& encoding = *plan.png16;
    const auto where = [&](size_t p) {
      return Location::Pixel(
          source.string(), frame_index, static_cast<int>(p % w), static_cast<int>(p / w));
    };
    for (size_t p = 0; p < n; ++p) {
      if (plan.integer) {
        const uint32_t id = channel.uints[p];
        if (id > 65535) {
          throw Error("id " + std::to_string(id) + " of layer '" + layer.name +
                          "' does not fit a 16-bit PNG (max 65535); use --to npy "
                          "or --to tiff",
                      where(p));
        }
        out[p] = static_cast<uint16_t>(id);
        continue;
      }
      EncodeOutcome outcome;
      const float value = channel.floats[p];
      out[p] = EncodeFloat(encoding, value, &outcome);
      if (outcome == EncodeOutcome::kInvalid) ++counts->invalid_pixels;
      if (outcome == EncodeOutcome::kClamped) {
        if (encoding.beyond_range_is_error && !options_.clamp_depth && value > 0)
          throw Error(BeyondRangeMessage(layer, encoding, value), where(p));
        ++counts->clamped_pixels;
      }
    }
    return mat;
  }

  const ExportOptions& options_;
  fs::path root_;
};

std::string NumpyType(const LayerPlan& plan, Target target) {
  if (target == Target::kPng16) return "uint16";
  if (target == Target::kTiff && plan.integer) return "int32";
  return plan.integer ? "uint32" : "float32";
}

nlohmann::ordered_json Describe(const LayerPlan& plan,
                                const ExportOptions& options,
                                const CollectionHeader& header) {
  const LayerInfo& layer = *plan.info;
  nlohmann::ordered_json j;
  j["semantic"] = layer.semantic;
  j["unit"] = layer.unit;
  if (layer.semantic == "depth" || layer.semantic == "worldposition")
    j["length_unit"] = header.conventions.world.length_unit;
  if (layer.depth_kind) j["depth_kind"] = DepthKindName(*layer.depth_kind);
  nlohmann::ordered_json exr_channels = nlohmann::ordered_json::array();
  for (const LayerChannel& c : layer.channels)
    exr_channels.push_back({{"name", c.name}, {"type", exr::PixelTypeName(c.type)}});
  j["exr_channels"] = exr_channels;
  j["dtype"] = NumpyType(plan, options.target);
  if (options.target == Target::kNpy) {
    j["file"] = layer.name + "/{stem}.npy";
    j["shape"] = layer.channels.size() == 1
                     ? "[height, width]"
                     : "[height, width, channels] (channels in exr_channels order)";
  } else {
    nlohmann::ordered_json files = nlohmann::ordered_json::object();
    for (size_t c = 0; c < layer.channels.size(); ++c)
      files[layer.channels[c].name] =
          layer.name + "/" + FileName("{stem}", layer, c, options.target);
    j["files"] = files;
    j["shape"] = "[height, width] (one file per channel)";
  }
  if (plan.png16 && !plan.png16->integer) {
    j["decode"] = "value = stored * scale + offset";
    j["scale"] = plan.png16->scale;
    j["offset"] = plan.png16->offset;
    j["quantisation"] = "round to nearest: |value - exr| <= scale / 2 inside the range";
    j["range"] = {DecodePng16(*plan.png16, plan.png16->lowest_valid()),
                  DecodePng16(*plan.png16, 65535)};
    if (plan.png16->invalid_stored) {
      j["invalid"] = {{"stored", *plan.png16->invalid_stored},
                      {"means", plan.png16->invalid_meaning}};
    } else {
      j["invalid"] = nullptr;
    }
    j["clamped_pixels"] = plan.summary.clamped_pixels;
  } else {
    j["decode"] = plan.integer && options.target == Target::kTiff
                      ? "exact: the bits of the EXR's uint32 (view as uint32)"
                      : "exact: the EXR's values";
    j["scale"] = 1;
    j["offset"] = 0;
    if (plan.integer) {
      j["invalid"] = nullptr;
    } else {
      j["invalid"] = {{"stored", "non-finite (NaN or inf), as in the EXR"},
                      {"means", "see docs/format.md for the layer"}};
    }
  }
  if (options.target == Target::kPng16 && plan.integer)
    j["clamped_pixels"] = 0;  // ids are exact or an error
  if (plan.integer) j["note"] = "0 = background/sky";
  j["frames_written"] = plan.summary.frames;
  j["invalid_pixels"] = plan.summary.invalid_pixels;
  return j;
}

}  // namespace

ExportSummary ExportLayers(const ExportOptions& options) {
  if (options.output.empty()) throw Error("no output folder (-o OUT)");
  if (!(options.depth_step > 0)) throw Error("--depth-step must be > 0");
  const CollectionReader reader(options.collection);
  const CollectionHeader& header = reader.header();
  const std::string collection_file = reader.collection_path().string();
  OutputGuard guard("lsds export-layers");
  GuardCollection(&guard, options.collection, CollectionAccess::kReadOnly);
  guard.CheckOutput(options.output, "-o");
  std::vector<LayerPlan> plans = PlanLayers(header, options, collection_file);

  AtomicDirectory folder(options.output, options.force);
  for (const LayerPlan& plan : plans) fs::create_directories(folder.temp_path() / plan.info->name);

  const FrameWriter writer(options, folder.temp_path());
  ExportSummary summary;
  std::vector<int64_t> frames;
  std::mutex mutex;
  std::atomic<int64_t> bytes{0};
  const int64_t in_file = static_cast<int64_t>(reader.frames_in_file());
  Progress progress("export-layers", in_file);
  const size_t batch = std::max<size_t>(2, size_t{2} * std::thread::hardware_concurrency());
  reader.ParallelForEachFrame(
      [&](const Frame& frame) {
        if (!options.frames.Contains(frame.index)) return;
        std::vector<LayerSummary> counts(plans.size());
        int64_t frame_bytes = 0;
        for (size_t i = 0; i < plans.size(); ++i) {
          const LayerInfo& layer = *plans[i].info;
          if (!layer.required && frame.files.count(layer.name) == 0) continue;
          frame_bytes += writer.Write(reader, frame, plans[i], &counts[i]);
          counts[i].frames = 1;
        }
        bytes += frame_bytes;
        progress.Add();
        const std::lock_guard<std::mutex> lock(mutex);
        frames.push_back(frame.index);
        for (size_t i = 0; i < plans.size(); ++i) {
          plans[i].summary.frames += counts[i].frames;
          plans[i].summary.invalid_pixels += counts[i].invalid_pixels;
          plans[i].summary.clamped_pixels += counts[i].clamped_pixels;
        }
      },
      batch);
  if (frames.empty()) {
    throw Error("no frame selected (the collection has " + std::to_string(in_file) + " frames)",
                Location(collection_file));
  }
  std::sort(frames.begin(), frames.end());

  nlohmann::ordered_json sidecar;
  sidecar["format"] = "lsds-layer-export";
  sidecar["format_version"] = "1.0";
  sidecar["collection"] = fs::absolute(options.collection).lexically_normal();
  sidecar["to"] = TargetName(options.target);
  sidecar["stem"] = "the frame index, zero-padded to 6 digits: {stem}";
  sidecar["frames"] = frames;
  nlohmann::ordered_json layers = nlohmann::ordered_json::object();
  for (const LayerPlan& plan : plans) {
    layers[plan.info->name] = Describe(plan, options, header);
    summary.layers.push_back(plan.summary);
    summary.files +=
        plan.summary.frames *
        (options.target == Target::kNpy ? 1 : static_cast<int64_t>(plan.info->channels.size()));
  }
  sidecar["layers"] = layers;
  const std::string text = sidecar.dump(2) + "\n";
  WriteFileAtomic(folder.temp_path() / kSidecarFile, text);
  folder.Commit();
  summary.frames = static_cast<int64_t>(frames.size());
  summary.bytes = bytes + static_cast<int64_t>(text.size());
  return summary;
}

}  // namespace lsds::layer_export
