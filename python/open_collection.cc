#include "python/open_collection.h"

#include <algorithm>
#include <cstddef>
#include <cstring>

#include <tbb/task_arena.h>

#include "libs/collection/json_io.h"
#include "libs/collection/json_stream.h"
#include "libs/collection/schema.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/flat_image.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "python/usage_error.h"

namespace lsds::python {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> ChannelNames(const LayerInfo& layer) {
  std::vector<std::string> names;
  for (const LayerChannel& c : layer.channels) names.push_back(c.name);
  return names;
}

// Runs `fn` on at most `threads` TBB threads: with 1, the calling thread does all the work and
// TBB starts no worker thread (a process that forks afterwards stays safe).
template <typename Fn>
auto InArena(int threads, Fn&& fn) {
  tbb::task_arena arena(threads);
  return arena.execute(std::forward<Fn>(fn));
}

// The channels of `image` in `names` order, each checked to hold the declared kind of values.
template <typename Image, typename Channel>
std::vector<const Channel*> DeclaredChannels(const Image& image,
                                             const std::vector<std::string>& names,
                                             const LayerInfo& layer,
                                             size_t values,
                                             const fs::path& path) {
  std::vector<const Channel*> channels;
  for (const std::string& name : names) {
    const Channel& c = image.Get(name);
    const bool integer = layer.FindChannel(name)->type == exr::PixelType::kUint;
    if ((integer ? c.uints.size() : c.floats.size()) != values) {
      throw Error("channel '" + name + "' is not of the declared type " +
                      exr::PixelTypeName(layer.FindChannel(name)->type),
                  Location(path.string()));
    }
    channels.push_back(&c);
  }
  return channels;
}

}  // namespace

OpenCollection::OpenCollection(const fs::path& root,
                               int threads,
                               const std::string& metadata_variant)
    : reader_(root), threads_(threads < 1 ? 1 : threads) {
  const std::string file = reader_.collection_path().string();
  const JsonSchema& schema = JsonSchema::Get("collection.schema.json", "frame");
  StreamJsonArrayMember(
      reader_.collection_path(), "frames", &header_json_, [&](nlohmann::json&& json, size_t index) {
        const std::string pointer = "/frames/" + std::to_string(index);
        schema.ValidateOrThrow(json, file, pointer);
        frames_.push_back(FrameFromJson(json, file, pointer));
        position_of_index_[frames_.back().index] = frames_.size() - 1;
        frame_json_.push_back(std::move(json));
      });
  header_json_.erase("frames");
  ReadMetadata(metadata_variant);
}

// The frame records (by index) of metadata variant `variant`, or of the truth metadata (the first
// variant that is not perturbed) when it is "".
void OpenCollection::ReadMetadata(const std::string& variant) {
  fs::path path;
  std::vector<std::string> files;
  for (const MetadataVariant& listed : header().metadata) {
    files.push_back(listed.file);
    if (variant.empty() ? !listed.perturbed : listed.file == variant) {
      path = reader_.root() / listed.file;
      metadata_variant_ = listed.file;
      break;
    }
  }
  if (!variant.empty() && path.empty()) {
    throw UsageError("metadata: '" + variant + "' is not a metadata variant of the collection (" +
                         (files.empty() ? std::string("it lists none") : Join(files, ", ")) + ")" +
                         DidYouMean(variant, files),
                     Location(reader_.collection_path().string(), "/metadata"));
  }
  std::error_code ec;
  if (path.empty() || !fs::is_regular_file(path, ec)) return;
  const std::string file = path.string();
  StreamJsonArrayMember(path, "frames", nullptr, [&](nlohmann::json&& json, size_t index) {
    const auto found = json.find("index");
    if (found == json.end() || !found->is_number_integer()) {
      throw Error("a metadata frame without an integer index",
                  Location(file, "/frames/" + std::to_string(index)));
    }
    const int64_t frame_index = found->get<int64_t>();
    metadata_[frame_index] = std::move(json);
  });
}

const nlohmann::json* OpenCollection::metadata(int64_t index) const {
  const auto it = metadata_.find(index);
  return it == metadata_.end() ? nullptr : &it->second;
}

std::optional<size_t> OpenCollection::PositionOfIndex(int64_t index) const {
  const auto it = position_of_index_.find(index);
  if (it == position_of_index_.end()) return std::nullopt;
  return it->second;
}

const LayerInfo& OpenCollection::FlatLayer(const std::string& name) const {
  std::vector<std::string> names;
  for (const LayerInfo& l : header().layers) names.push_back(l.name);
  const LayerInfo* layer = header().FindLayer(name);
  if (layer == nullptr) {
    throw UsageError("the collection " + reader_.root().string() + " has no layer '" + name + "'" +
                     DidYouMean(name, names) + " (layers: " + Join(names, ", ") + ")");
  }
  if (layer->deep) {
    throw UsageError("'" + name +
                     "' is a deep layer (several samples per pixel): read it with Frame.bundle()");
  }
  if (layer->channels.empty()) {
    throw Error("layer '" + name + "' declares no channels",
                Location(reader_.collection_path().string(), "/layers"));
  }
  return *layer;
}

const LayerInfo& OpenCollection::DeepLayer(const std::string& name) const {
  if (name.empty()) {
    for (const LayerInfo& l : header().layers)
      if (l.deep && l.semantic == "bundle") return l;
    throw UsageError("the collection " + reader_.root().string() + " has no bundle layer");
  }
  const LayerInfo* layer = header().FindLayer(name);
  if (layer == nullptr || !layer->deep) {
    std::vector<std::string> deep;
    for (const LayerInfo& l : header().layers)
      if (l.deep) deep.push_back(l.name);
    throw UsageError("the collection " + reader_.root().string() + " has no deep layer '" + name +
                     "'" + DidYouMean(name, deep) + " (deep layers: " + Join(deep, ", ") + ")");
  }
  return *layer;
}

LayerArray OpenCollection::ReadLayer(size_t position,
                                     const std::string& name,
                                     bool channels_first) const {
  const LayerInfo& layer = FlatLayer(name);
  LayerArray out;
  bool any_float = false;
  for (const LayerChannel& c : layer.channels)
    (c.type == exr::PixelType::kUint ? out.integer : any_float) = true;
  if (out.integer && any_float) {
    throw Error("layer '" + name + "' mixes UINT and float channels, which one array cannot hold",
                Location(reader_.collection_path().string(), "/layers"));
  }
  const Frame& f = frames_[position];
  const std::vector<std::string> names = ChannelNames(layer);
  InArena(threads_, [&] {
    // Through the reader: residual worldposition and motion files decode to their floats.
    const exr::FlatImage image = reader_.ReadFlatLayer(f, name, names);
    const size_t n = image.pixel_count(), count = names.size();
    out.shape = {image.height(), image.width()};
    if (channels_first) {
      out.shape.insert(out.shape.begin(), static_cast<int64_t>(count));
    } else if (count > 1) {
      out.shape.push_back(static_cast<int64_t>(count));
    }
    const auto channels = DeclaredChannels<exr::FlatImage, exr::FlatChannel>(
        image, names, layer, n, reader_.LayerPath(f, name));
    auto interleave = [&](auto member, auto* values) {
      values->resize(n * count);
      for (size_t c = 0; c < count; ++c) {
        const auto& from = channels[c]->*member;
        if (channels_first || count == 1) {
          std::copy(from.begin(), from.end(), values->begin() + static_cast<std::ptrdiff_t>(c * n));
        } else {
          for (size_t p = 0; p < n; ++p) (*values)[p * count + c] = from[p];
        }
      }
    };
    if (out.integer) {
      interleave(&exr::FlatChannel::uints, &out.uints);
    } else {
      interleave(&exr::FlatChannel::floats, &out.floats);
    }
  });
  return out;
}

BundleArrays OpenCollection::ReadBundle(size_t position, const std::string& name) const {
  const LayerInfo& layer = DeepLayer(name);
  const Frame& f = frames_[position];
  BundleArrays out;
  InArena(threads_, [&] {
    // Through the reader: compact and residual bundles decode to the full layout's samples.
    const exr::DeepImage image = reader_.ReadDeepLayer(f, layer.name, ChannelNames(layer));
    std::vector<std::string> names = ChannelNames(layer);
    if (names.empty())
      for (const exr::DeepChannel& c : image.channels()) names.push_back(c.name);
    out.width = image.width();
    out.height = image.height();
    out.counts = image.sample_counts();
    out.offsets = image.offsets();
    const size_t samples = image.total_samples(), record = 4 * names.size();
    std::vector<const exr::DeepChannel*> channels;
    for (const std::string& channel : names) {
      const exr::DeepChannel& c = image.Get(channel);
      const bool integer = c.type == exr::PixelType::kUint;
      out.fields.push_back({channel, integer ? exr::PixelType::kUint : exr::PixelType::kFloat});
      channels.push_back(&c);
    }
    out.records.resize(samples * record);
    for (size_t c = 0; c < channels.size(); ++c) {
      const bool integer = out.fields[c].type == exr::PixelType::kUint;
      const void* from = integer ? static_cast<const void*>(channels[c]->uints.data())
                                 : static_cast<const void*>(channels[c]->floats.data());
      for (size_t s = 0; s < samples; ++s)
        std::memcpy(&out.records[s * record + 4 * c], static_cast<const char*>(from) + 4 * s, 4);
    }
  });
  return out;
}

}  // namespace lsds::python
