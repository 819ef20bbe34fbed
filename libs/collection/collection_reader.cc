#include "libs/collection/collection_reader.h"

#include <optional>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "libs/collection/collection_read_once.h"
#include "libs/collection/frame_text_reader.h"
#include "libs/collection/json_array_split.h"
#include "libs/collection/json_io.h"
#include "libs/collection/json_stream.h"
#include "libs/collection/motion_layout.h"
#include "libs/collection/schema.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/util/error.h"

namespace lsds {

namespace fs = std::filesystem;

bool LooksLikeCollection(const fs::path& root) {
  std::error_code ec;
  return fs::is_regular_file(root / kCollectionFile, ec);
}

void CheckCollectionFolder(const fs::path& root) {
  std::error_code ec;
  if (!fs::is_directory(root, ec)) {
    throw Error(fs::exists(root, ec) ? "is not a folder" : "does not exist",
                Location(root.string()));
  }
  if (!LooksLikeCollection(root)) {
    throw Error("is not an lsds collection: it has no " + std::string(kCollectionFile),
                Location(root.string()));
  }
}

CollectionReader::CollectionReader(const fs::path& root, ReaderOptions options)
    : root_(root), options_(options) {
  CheckCollectionFolder(root_);
  const std::string file = collection_path().string();
  nlohmann::json header_json;
  frames_in_file_ = ReadCollectionHeader(collection_path(), &header_json);
  if (options_.validate_schema) {
    JsonSchema::Get("collection.schema.json").ValidateOrThrow(header_json, file);
  }
  header_ = HeaderFromJson(header_json, file);
}

namespace {

// The header text the split gives, parsed; false (the DOM stream reports it)
// when it is not an object.
// The DOM path of a frame: the frame schema (unless `options` leave it out),
// then FrameFromJson, each reporting at the frame's JSON pointer.
Frame CheckedFrameFromJson(const nlohmann::json& json,
                           size_t index,
                           const std::string& file,
                           const ReaderOptions& options) {
  const std::string pointer = "/frames/" + std::to_string(index);
  if (options.validate_schema) {
    JsonSchema::Get("collection.schema.json", "frame").ValidateOrThrow(json, file, pointer);
  }
  return FrameFromJson(json, file, pointer);
}

bool ParseHeaderText(const std::string& text, nlohmann::json* header) {
  try {
    *header = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    return false;
  }
  return header->is_object();
}

}  // namespace

bool ReadCollectionHeaderBeforeFrames(const fs::path& path, nlohmann::json* header) {
  std::string text;
  if (!ReadJsonTextBeforeArray(path, "frames", &text)) return false;
  return ParseHeaderText(text + "]}", header);
}

namespace {

// The header of a one-pass read, or null when the file does not allow it: a
// header the usual reader would refuse is left to it, which reports what is
// wrong first (a syntax error anywhere in the file before the header's).
std::optional<CollectionHeader> HeaderBeforeFrames(const fs::path& path,
                                                   const ReaderOptions& options,
                                                   nlohmann::json* header_json) {
  if (!ReadCollectionHeaderBeforeFrames(path, header_json)) return std::nullopt;
  if (options.validate_schema &&
      !JsonSchema::Get("collection.schema.json").Validate(*header_json).empty())
    return std::nullopt;
  try {
    return HeaderFromJson(*header_json, path.string());
  } catch (const Error&) {
    return std::nullopt;
  }
}

}  // namespace

CollectionHeader ReadCollectionOnce(const fs::path& root,
                                    const ReadCollection& read,
                                    ReaderOptions options) {
  CheckCollectionFolder(root);
  const fs::path path = root / kCollectionFile;
  nlohmann::json header_before;
  if (const std::optional<CollectionHeader> header =
          HeaderBeforeFrames(path, options, &header_before)) {
    const std::string file = path.string();
    bool whole_header = false;
    read(*header, [&](const std::function<void(const Frame&)>& fn) {
      nlohmann::json header_after;
      StreamCollectionFramesAndHeader(
          path,
          [&](Frame&& frame, size_t) { fn(frame); },
          [&](nlohmann::json&& json, size_t index) {
            fn(CheckedFrameFromJson(json, index, file, options));
          },
          CollectionReader::FramePath::kFastWhereItFits,
          &header_after);
      whole_header = header_after == header_before;
    });
    if (whole_header) return *header;
  }
  // Members after the frames (or a header to report): the usual reader.
  const CollectionReader reader(root, options);
  read(reader.header(),
       [&](const std::function<void(const Frame&)>& fn) { reader.ForEachFrame(fn); });
  return reader.header();
}

size_t ReadCollectionHeader(const std::filesystem::path& path, nlohmann::json* header) {
  std::string header_text;
  FrameTextReader frames;
  size_t count = 0;
  const bool split = SplitJsonArrayMember(
      path,
      "frames",
      &header_text,
      [&](std::string_view text, size_t) { return frames.IsWellFormed(text); },
      &count);
  if (split && ParseHeaderText(header_text, header)) return count;
  // The DOM stream: it reports what the fast path did not take at its line
  // and column, or reads it.
  *header = nlohmann::json();
  return StreamJsonArrayMember(path, "frames", header, nullptr);
}

void CollectionReader::ForEachFrameJson(
    const std::function<void(const nlohmann::json&, const std::string&)>& fn) const {
  StreamJsonArrayMember(
      collection_path(), "frames", nullptr, [&](nlohmann::json&& frame, size_t index) {
        fn(frame, "/frames/" + std::to_string(index));
      });
}

void CollectionReader::ForEachFrame(const std::function<void(const Frame&)>& fn) const {
  ForEachFrame(fn, FramePath::kFastWhereItFits);
}

void CollectionReader::ForEachFrame(const std::function<void(const Frame&)>& fn,
                                    FramePath path) const {
  const std::string file = collection_path().string();
  StreamCollectionFrames(
      collection_path(),
      [&](Frame&& frame, size_t) { fn(frame); },
      [&](nlohmann::json&& json, size_t index) {
        fn(CheckedFrameFromJson(json, index, file, options_));
      },
      path);
}

void StreamCollectionFrames(const std::filesystem::path& path,
                            const std::function<void(Frame&&, size_t)>& on_frame,
                            const std::function<void(nlohmann::json&&, size_t)>& on_json,
                            CollectionReader::FramePath frame_path) {
  StreamCollectionFramesAndHeader(path, on_frame, on_json, frame_path, nullptr);
}

size_t StreamCollectionFramesAndHeader(const std::filesystem::path& path,
                                       const std::function<void(Frame&&, size_t)>& on_frame,
                                       const std::function<void(nlohmann::json&&, size_t)>& on_json,
                                       CollectionReader::FramePath frame_path,
                                       nlohmann::json* header) {
  size_t done = 0;
  if (frame_path == CollectionReader::FramePath::kFastWhereItFits) {
    // Each frame's text read by simdjson into the Frame; a frame the fast path
    // does not take is parsed from its text for the DOM path.
    FrameTextReader fast;
    Frame frame;
    std::string header_text;
    const bool split = SplitJsonArrayMember(
        path,
        "frames",
        header != nullptr ? &header_text : nullptr,
        [&](std::string_view text, size_t index) {
          if (fast.Read(text, &frame)) {
            on_frame(std::move(frame), index);
            return true;
          }
          nlohmann::json json;
          try {
            json = nlohmann::json::parse(text);
          } catch (const nlohmann::json::exception&) {
            return false;  // the stream below reports it at its line and column
          }
          on_json(std::move(json), index);
          return true;
        },
        &done);
    if (split && (header == nullptr || ParseHeaderText(header_text, header))) return done;
  }
  // The DOM stream, from the first frame not handed out yet.
  if (header != nullptr) *header = nlohmann::json();
  return StreamJsonArrayMember(path, "frames", header, [&](nlohmann::json&& json, size_t index) {
    if (index >= done) on_json(std::move(json), index);
  });
}

void CollectionReader::ParallelForEachFrame(const std::function<void(const Frame&)>& fn,
                                            size_t batch_size) const {
  std::vector<Frame> batch;
  batch.reserve(batch_size);
  auto flush = [&] {
    tbb::parallel_for(size_t{0}, batch.size(), [&](size_t i) { fn(batch[i]); });
    batch.clear();
  };
  ForEachFrame([&](const Frame& frame) {
    batch.push_back(frame);
    if (batch.size() == batch_size) flush();
  });
  flush();
}

fs::path CollectionReader::LayerPath(const Frame& frame, const std::string& layer) const {
  const auto it = frame.files.find(layer);
  if (it == frame.files.end()) {
    Location where{collection_path().string()};
    where.frame = frame.index;
    throw Error("frame has no file for layer '" + layer + "'", where);
  }
  return root_ / it->second;
}

exr::FlatImage CollectionReader::ReadFlatLayer(const Frame& frame,
                                               const std::string& layer,
                                               const std::vector<std::string>& channels) const {
  const fs::path path = LayerPath(frame, layer);
  const LayerInfo* info = header_.FindLayer(layer);
  exr::FlatImage image = ReadFlatLayerFile(
      path, info != nullptr ? info->semantic : "", channels, [&](const std::string& depth_layer) {
        return PredictionOfFrame(root_, header_, frame, depth_layer);
      });
  CheckLayerSize(frame, layer, path, image.width(), image.height());
  return image;
}

exr::DeepImage CollectionReader::ReadDeepLayer(const Frame& frame,
                                               const std::string& layer,
                                               const std::vector<std::string>& channels) const {
  const fs::path path = LayerPath(frame, layer);
  exr::DeepImage image = ReadBundleExr(path, channels);  // either bundle layout
  CheckLayerSize(frame, layer, path, image.width(), image.height());
  return image;
}

void CheckLayerSize(
    const Frame& frame, const std::string& layer, const fs::path& path, int width, int height) {
  const int camera_width = frame.camera.intrinsics.width;
  const int camera_height = frame.camera.intrinsics.height;
  if (width == camera_width && height == camera_height) return;
  Location where(path.string());
  where.frame = frame.index;
  throw Error("layer '" + layer + "' is " + std::to_string(width) + "x" + std::to_string(height) +
                  " but the frame's camera is " + std::to_string(camera_width) + "x" +
                  std::to_string(camera_height),
              where);
}

MetadataReader::MetadataReader(const fs::path& path, ReaderOptions options)
    : path_(path), options_(options) {
  std::error_code ec;
  if (!fs::is_regular_file(path_, ec))
    throw Error("metadata file does not exist", Location(path_.string()));
  nlohmann::json header_json;
  StreamJsonArrayMember(path_, "frames", &header_json, nullptr);
  if (options_.validate_schema) {
    JsonSchema::Get("metadata.schema.json").ValidateOrThrow(header_json, path_.string());
  }
  header_ = MetadataHeaderFromJson(header_json, path_.string());
}

void MetadataReader::ForEachFrame(const std::function<void(const MetadataFrame&)>& fn) const {
  const std::string file = path_.string();
  const JsonSchema& schema = JsonSchema::Get("metadata.schema.json", "frame");
  StreamJsonArrayMember(path_, "frames", nullptr, [&](nlohmann::json&& json, size_t index) {
    const std::string pointer = "/frames/" + std::to_string(index);
    if (options_.validate_schema) schema.ValidateOrThrow(json, file, pointer);
    fn(MetadataFrameFromJson(json, file, pointer));
  });
}

exr::FlatImage ReadFlatLayerFile(const fs::path& path,
                                 const std::string& semantic,
                                 const std::vector<std::string>& channels,
                                 const PredictionSource& prediction) {
  if (semantic == "worldposition") return ReadWorldPositionExr(path, channels, prediction);
  if (semantic == "motion") return ReadMotionExr(path, channels, prediction);
  return exr::ReadFlatExr(path, channels);
}

}  // namespace lsds
