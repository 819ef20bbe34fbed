#include "libs/collection/collection_writer.h"

#include "libs/collection/json_io.h"
#include "libs/util/error.h"

namespace lsds {

CollectionWriter::CollectionWriter(const std::filesystem::path& root,
                                   const CollectionHeader& header)
    : expected_(header.frame_count),
      writer_(root / kCollectionFile, HeaderToJson(header), "frames") {}

void CollectionWriter::Append(const Frame& frame) { writer_.Append(FrameToJson(frame)); }

void CollectionWriter::Commit() {
  if (static_cast<int64_t>(writer_.count()) != expected_) {
    throw Error("collection writer: header declares " + std::to_string(expected_) + " frames, " +
                std::to_string(writer_.count()) + " were written");
  }
  writer_.Commit();
}

static nlohmann::json MergedMetadataHeader(const MetadataHeader& header,
                                           const nlohmann::json& extra) {
  nlohmann::json json = MetadataHeaderToJson(header);
  for (auto it = extra.begin(); it != extra.end(); ++it) json[it.key()] = it.value();
  return json;
}

MetadataWriter::MetadataWriter(const std::filesystem::path& path,
                               const MetadataHeader& header,
                               const nlohmann::json& extra_members)
    : expected_(header.frame_count),
      writer_(path, MergedMetadataHeader(header, extra_members), "frames") {}

void MetadataWriter::Append(const MetadataFrame& frame) {
  writer_.Append(MetadataFrameToJson(frame));
}

void MetadataWriter::Commit() {
  if (static_cast<int64_t>(writer_.count()) != expected_) {
    throw Error("metadata writer: header declares " + std::to_string(expected_) + " frames, " +
                std::to_string(writer_.count()) + " were written");
  }
  writer_.Commit();
}

}  // namespace lsds
