#include "libs/collection/model.h"

namespace lsds {

using exr::Compression;
using exr::PixelType;

const LayerChannel* LayerInfo::FindChannel(const std::string& channel) const {
  for (const LayerChannel& c : channels) {
    if (c.name == channel) return &c;
  }
  return nullptr;
}

const LayerInfo* CollectionHeader::FindLayer(const std::string& name) const {
  for (const LayerInfo& layer : layers) {
    if (layer.name == name) return &layer;
  }
  return nullptr;
}

const LayerInfo* CollectionHeader::FindLayerBySemantic(const std::string& semantic) const {
  for (const LayerInfo& layer : layers) {
    if (layer.semantic == semantic) return &layer;
  }
  return nullptr;
}

const ClassInfo* CollectionHeader::FindClass(uint32_t id) const {
  for (const ClassInfo& c : classes) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

exr::HeaderCamera HeaderCameraOf(const CameraTruth& camera) {
  Eigen::Matrix4d cam_from_world = Eigen::Matrix4d::Identity();
  cam_from_world.topLeftCorner<3, 3>() = camera.cam_from_world_rotation;
  cam_from_world.topRightCorner<3, 1>() = camera.cam_from_world_translation;
  return {cam_from_world, camera.intrinsics.NdcFromCam() * cam_from_world};
}

Rigid3d CamFromWorld(const CameraTruth& camera) {
  return Rigid3d(Eigen::Quaterniond(camera.cam_from_world_rotation).normalized(),
                 camera.cam_from_world_translation);
}

void SetCamFromWorld(const Rigid3d& cam_from_world, CameraTruth* camera) {
  camera->cam_from_world_rotation = cam_from_world.rotation.toRotationMatrix();
  camera->cam_from_world_translation = cam_from_world.translation;
}

const std::vector<std::string>& StandardLayerSemantics() {
  static const std::vector<std::string> semantics = {"rgb",
                                                     "classid",
                                                     "instanceid",
                                                     "depth",
                                                     "normal",
                                                     "worldposition",
                                                     "shadow",
                                                     "motion",
                                                     "bundle"};
  return semantics;
}

LayerInfo StandardLayer(const std::string& semantic, DepthKind depth_kind) {
  LayerInfo layer;
  layer.name = semantic;
  layer.semantic = semantic;
  layer.compression = Compression::kZip;
  if (semantic == "rgb") {
    layer.channels = {{"R", PixelType::kHalf}, {"G", PixelType::kHalf}, {"B", PixelType::kHalf}};
    layer.compression = Compression::kPiz;
    layer.unit = "linear radiance";
    layer.description = "scene-linear HDR colour, spatially multisampled";
  } else if (semantic == "classid" || semantic == "instanceid") {
    layer.channels = {{"id", PixelType::kUint}};
    layer.unit = "id";
    layer.description = semantic == "classid" ? "class id of the closest surface at the pixel "
                                                "centre sample; 0 background"
                                              : "instance id of the closest surface at the pixel "
                                                "centre sample; 0 background";
  } else if (semantic == "depth") {
    layer.channels = {{"Z", PixelType::kFloat}};
    layer.unit = "world length unit";
    layer.depth_kind = depth_kind;
    layer.description = "distance of the closest surface; +inf for sky";
  } else if (semantic == "normal") {
    layer.channels = {{"X", PixelType::kFloat}, {"Y", PixelType::kFloat}, {"Z", PixelType::kFloat}};
    layer.unit = "unit vector, world frame";
    layer.description = "surface normal facing the camera; (0, 0, 0) for sky";
  } else if (semantic == "worldposition") {
    layer.channels = {{"X", PixelType::kFloat}, {"Y", PixelType::kFloat}, {"Z", PixelType::kFloat}};
    layer.unit = "world length unit";
    layer.description = "hit point in world coordinates; +inf for sky";
  } else if (semantic == "shadow") {
    layer.channels = {{"Y", PixelType::kFloat}};
    layer.unit = "ratio";
    layer.description = "final / unshadowed shading in [0, 1]: 0 full shadow, 1 none";
  } else if (semantic == "motion") {
    layer.channels = {{"X", PixelType::kFloat}, {"Y", PixelType::kFloat}};
    layer.unit = "screen-normalized";
    layer.description =
        "0.5 + 0.5 * (position now - position in the previous frame) / image "
        "size";
  } else if (semantic == "bundle") {
    layer.deep = true;
    layer.compression = Compression::kZips;
    layer.channels = {{"instanceid", PixelType::kUint},
                      {"classid", PixelType::kUint},
                      {"Z", PixelType::kFloat},
                      {"NX", PixelType::kFloat},
                      {"NY", PixelType::kFloat},
                      {"NZ", PixelType::kFloat},
                      {"SX", PixelType::kFloat},
                      {"SY", PixelType::kFloat}};
    layer.unit = "samples";
    layer.depth_kind = depth_kind;
    layer.description =
        "every sub-pixel sample: ids, depth, normal, position in the pixel; "
        "sample 0 is "
        "the one nearest the pixel centre";
  }
  return layer;
}

}  // namespace lsds
