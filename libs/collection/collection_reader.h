// Reading a collection folder: the header at once, the frames as a stream.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "libs/collection/model.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/flat_image.h"

namespace lsds {

struct ReaderOptions {
  bool validate_schema = true;  // check collection.json (header and each frame) against its schema
};

class CollectionReader {
 public:
  // Opens `root`/collection.json: parses and validates the header, counts the
  // frames. Throws lsds::Error naming the file (and the JSON pointer or
  // line:column) if it is not a collection.
  explicit CollectionReader(const std::filesystem::path& root, ReaderOptions options = {});

  const std::filesystem::path& root() const { return root_; }
  std::filesystem::path collection_path() const { return root_ / kCollectionFile; }
  const CollectionHeader& header() const { return header_; }
  size_t frames_in_file() const { return frames_in_file_; }

  // Frames in file order, one at a time. Each frame is schema-checked and
  // parsed before `fn` sees it: by the fast path (frame_text_reader.h) where
  // the frame fits it, else by the DOM path (schema, then FrameFromJson), the
  // one that reports errors. Both give the same Frame.
  void ForEachFrame(const std::function<void(const Frame&)>& fn) const;
  enum class FramePath { kFastWhereItFits, kDomOnly };
  // The same with the path chosen (tests compare the two).
  void ForEachFrame(const std::function<void(const Frame&)>& fn, FramePath path) const;
  // The raw JSON of each frame with its JSON pointer ("/frames/17"), for checks
  // on the text itself.
  void ForEachFrameJson(
      const std::function<void(const nlohmann::json&, const std::string&)>& fn) const;
  // Frames in batches of `batch_size`, each batch processed in parallel (TBB);
  // memory is bounded by the batch, not the collection. `fn` must be
  // thread-safe.
  void ParallelForEachFrame(const std::function<void(const Frame&)>& fn,
                            size_t batch_size = 32) const;

  // Absolute path of a frame's file for `layer`; throws when the frame has
  // none.
  std::filesystem::path LayerPath(const Frame& frame, const std::string& layer) const;

  // Read a frame's layer file and check its size against the frame's camera
  // (every command reads layers through these): a wrong-size layer is an
  // lsds::Error naming the file, the frame and the layer.
  exr::FlatImage ReadFlatLayer(const Frame& frame,
                               const std::string& layer,
                               const std::vector<std::string>& channels) const;
  exr::DeepImage ReadDeepLayer(const Frame& frame,
                               const std::string& layer,
                               const std::vector<std::string>& channels) const;

 private:
  std::filesystem::path root_;
  ReaderOptions options_;
  CollectionHeader header_;
  size_t frames_in_file_ = 0;
};

// The members of the collection.json at `path` but its frames (left an empty
// array) into `*header`, and the number of frames: what StreamJsonArrayMember
// gives, by the fast split (json_array_split.h) with every frame's syntax
// checked by simdjson; a file that does not fit it goes to
// StreamJsonArrayMember itself, which reads it or reports what is wrong at its
// line and column.
size_t ReadCollectionHeader(const std::filesystem::path& path, nlohmann::json* header);

// The frames of the collection.json at `path` in file order, one at a time:
// each frame the fast path takes (frame_text_reader.h: what the frame schema
// and FrameFromJson check, done in code) to `on_frame`, read; every other one
// to `on_json` as nlohmann's DOM, for the schema and FrameFromJson, which
// report it. A syntax error throws lsds::Error at its line:column (the DOM
// stream's message), after the frames before it were handed out.
// CollectionReader::ForEachFrame and `lsds validate` read frames through it.
void StreamCollectionFrames(
    const std::filesystem::path& path,
    const std::function<void(Frame&&, size_t index)>& on_frame,
    const std::function<void(nlohmann::json&&, size_t index)>& on_json,
    CollectionReader::FramePath frame_path = CollectionReader::FramePath::kFastWhereItFits);

// Throws lsds::Error naming `path`, the frame and the layer unless the layer is
// width x height, the size of the frame's camera.
void CheckLayerSize(const Frame& frame,
                    const std::string& layer,
                    const std::filesystem::path& path,
                    int width,
                    int height);

// True if `root` holds a collection.json (says nothing about its validity).
bool LooksLikeCollection(const std::filesystem::path& root);
// Throws lsds::Error naming `root` when it is not a folder holding a
// collection.json.
void CheckCollectionFolder(const std::filesystem::path& root);

// metadata.json and its variants, streamed the same way.
class MetadataReader {
 public:
  explicit MetadataReader(const std::filesystem::path& path, ReaderOptions options = {});
  const MetadataHeader& header() const { return header_; }
  const std::filesystem::path& path() const { return path_; }
  void ForEachFrame(const std::function<void(const MetadataFrame&)>& fn) const;

 private:
  std::filesystem::path path_;
  ReaderOptions options_;
  MetadataHeader header_;
};

// Reads one flat layer file of semantic `semantic` in whichever layout it is
// stored: worldposition and motion float or residual (the prediction inputs
// asked from `prediction` only for residual files), every other layer as
// stored. The one dispatch of CollectionReader and the validator.
exr::FlatImage ReadFlatLayerFile(const std::filesystem::path& path,
                                 const std::string& semantic,
                                 const std::vector<std::string>& channels,
                                 const PredictionSource& prediction);

}  // namespace lsds
