// The collection behind the Python module (docs/python.md): every frame of collection.json held in
// memory, parsed and as the file has it, and the layers decoded through the collection reader into
// plain arrays. No Python here: the bindings release the GIL around these calls.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/collection/collection_reader.h"
#include "libs/collection/model.h"
#include "libs/exr/exr_types.h"

namespace lsds::python {

// A decoded flat layer: (height, width) or (height, width, channels) row-major, the channels
// interleaved in the layer table's order, as `lsds export-layers --to npy` writes it.
struct LayerArray {
  std::vector<int64_t> shape;
  bool integer = false;       // every channel UINT: `uints`; else HALF/FLOAT: `floats`
  std::vector<float> floats;  // HALF widened to float (exact)
  std::vector<uint32_t> uints;
};

// A decoded deep layer (the pixel bundle): sample counts per pixel, their prefix sums, and the
// samples as packed records of 4-byte fields (uint32 or float32), fields in the layer table's
// order (bundles: instanceid, classid, Z, NX, NY, NZ, SX, SY, whichever layout stores them).
struct BundleArrays {
  int width = 0;
  int height = 0;
  std::vector<uint32_t> counts;          // height * width
  std::vector<uint64_t> offsets;         // height * width + 1: pixel p's samples are [p, p + 1)
  std::vector<exr::ChannelSpec> fields;  // kUint or kFloat (HALF read as float)
  std::vector<uint8_t> records;          // offsets.back() * 4 * fields.size() bytes
};

// Read-only after construction, so that any thread may decode through it.
class OpenCollection {
 public:
  // Reads collection.json (header and frames, each schema-checked, as CollectionReader does) and
  // the records of one metadata variant (collection.json `metadata`, docs/format.md): the file
  // `metadata_variant` names, or the truth metadata (the first unperturbed variant) when it is
  // empty. `threads`: TBB threads one decode may use; 1 starts none. Throws lsds::Error located
  // like the CLI's messages; UsageError for a variant the collection does not list.
  OpenCollection(const std::filesystem::path& root,
                 int threads,
                 const std::string& metadata_variant = "");

  const CollectionReader& reader() const { return reader_; }
  const CollectionHeader& header() const { return reader_.header(); }
  const nlohmann::json& header_json() const { return header_json_; }  // without "frames"
  int threads() const { return threads_; }
  size_t size() const { return frames_.size(); }
  const Frame& frame(size_t position) const { return frames_[position]; }
  const nlohmann::json& frame_json(size_t position) const { return frame_json_[position]; }
  // The chosen metadata variant's record of the frame with this index; null when there is none.
  const nlohmann::json* metadata(int64_t index) const;
  // The chosen metadata variant (its `file`), "" when the collection lists none.
  const std::string& metadata_variant() const { return metadata_variant_; }
  std::optional<size_t> PositionOfIndex(int64_t index) const;

  // The layer table's entry: a flat layer, or a deep one (empty name: the first of semantic
  // "bundle"). Throws lsds::Error (no location: the caller's argument) for an unknown name or a
  // layer of the other kind.
  const LayerInfo& FlatLayer(const std::string& name) const;
  const LayerInfo& DeepLayer(const std::string& name) const;

  // Decodes a layer of the frame at `position` with the project's readers (residual layouts
  // included), on at most threads() TBB threads.
  // `channels_first`: shape (channels, height, width), each channel's plane as the reader
  // decodes it (no interleaving: what PyTorch's layout wants, with one copy less).
  LayerArray ReadLayer(size_t position, const std::string& name, bool channels_first = false) const;
  BundleArrays ReadBundle(size_t position, const std::string& name) const;

 private:
  void ReadMetadata(const std::string& variant);

  CollectionReader reader_;
  int threads_ = 1;
  nlohmann::json header_json_;
  std::vector<Frame> frames_;
  std::vector<nlohmann::json> frame_json_;
  std::map<int64_t, size_t> position_of_index_;
  std::map<int64_t, nlohmann::json> metadata_;
  std::string metadata_variant_;
};

}  // namespace lsds::python
