// Writing collection.json and metadata.json frame by frame, atomically.
#pragma once

#include <filesystem>

#include "libs/collection/json_stream.h"
#include "libs/collection/model.h"

namespace lsds {

// Frames are appended in order; Commit() checks that their number equals
// header.frame_count and renames the file into place.
class CollectionWriter {
 public:
  CollectionWriter(const std::filesystem::path& root, const CollectionHeader& header);
  void Append(const Frame& frame);
  void Commit();

 private:
  int64_t expected_;
  JsonArrayWriter writer_;
};

class MetadataWriter {
 public:
  MetadataWriter(const std::filesystem::path& path,
                 const MetadataHeader& header,
                 const nlohmann::json& extra_members = nlohmann::json::object());
  void Append(const MetadataFrame& frame);
  void Commit();

 private:
  int64_t expected_;
  JsonArrayWriter writer_;
};

}  // namespace lsds
