// JSON form of the collection model (docs/format.md). Readers assume the
// document passed its schema (schema.h) and still throw lsds::Error with file
// and JSON pointer on anything the schema cannot see.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "libs/collection/model.h"

namespace lsds {

nlohmann::json HeaderToJson(const CollectionHeader& header);  // "frames" left empty
nlohmann::json FrameToJson(const Frame& frame);
// A camera rig ("rig" of collection.json and of plans; docs/format.md, "Camera rigs").
nlohmann::json RigToJson(const Rig& rig);
Rig RigFromJson(const nlohmann::json& j);
CollectionHeader HeaderFromJson(const nlohmann::json& json, const std::string& file);
Frame FrameFromJson(const nlohmann::json& json,
                    const std::string& file,
                    const std::string& pointer);

nlohmann::json MetadataHeaderToJson(const MetadataHeader& header);
nlohmann::json MetadataFrameToJson(const MetadataFrame& frame);
MetadataHeader MetadataHeaderFromJson(const nlohmann::json& json, const std::string& file);
MetadataFrame MetadataFrameFromJson(const nlohmann::json& json,
                                    const std::string& file,
                                    const std::string& pointer);

// The metadata that a perfect platform would measure for a frame (metadata
// equals truth).
MetadataFrame TruthMetadata(const Frame& frame, const WorldFrame& world);

nlohmann::json Box2dToJson(const std::optional<Box2d>& box);
nlohmann::json Matrix3ToJson(const Eigen::Matrix3d& m);
nlohmann::json Vector3ToJson(const Eigen::Vector3d& v);

}  // namespace lsds
