#include "importers/ue_mrq/ue_mrq_importer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include <nlohmann/json.hpp>

#include "importers/cryptomatte.h"
#include "importers/source_exr.h"
#include "importers/source_json.h"
#include "importers/unreal_frame.h"
#include "libs/geometry/camera.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"
#include "libs/util/strings.h"

namespace lsds::import {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Attribute names differ between releases (legacy queue: unreal/camera/...,
// later ones per layer: unreal/layerData/rgba/...); the first present wins.
std::vector<std::string> CameraKeys(const std::string& field) {
  return {"unreal/camera/" + field, "unreal/layerData/rgba/" + field};
}
std::vector<std::string> LensKeys(const std::string& field) {
  return {"unreal/camera/FinalImage/" + field, "unreal/layerData/rgba/" + field};
}

// "Shot.0042" -> ("Shot", 42).
bool SplitFrameName(const std::string& stem, std::string* sequence, int64_t* number) {
  size_t end = stem.size();
  size_t begin = end;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) --begin;
  if (begin == end || end - begin > 12) return false;
  const std::optional<int64_t> parsed =
      ParseInteger(stem.substr(begin), 0, std::numeric_limits<int64_t>::max());
  if (!parsed) return false;
  *number = *parsed;
  std::string prefix = stem.substr(0, begin);
  while (!prefix.empty() && (prefix.back() == '.' || prefix.back() == '_' || prefix.back() == '-'))
    prefix.pop_back();
  *sequence = prefix.empty() ? "sequence" : prefix;
  return true;
}

Eigen::Vector3d Vector3(const json& j) {
  if (!j.is_array() || j.size() != 3) throw json::type_error::create(302, "expected [x, y, z]", &j);
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

// The camera of the data window (the collection's image) for a horizontal
// FOV. MRQ's fov is that of the whole rendered image: the view's FOV is
// inflated by the overscan before the projection is built and written
// (MoviePipelineImagePassBase.cpp GetSceneViewForSampleState), and the EXR's
// data window holds that render with the overscan, the display window the
// target resolution (MoviePipelineCameraSetting overscan_percentage). With
// `of_display_window` (other renderers' files, e.g. V-Ray's crop renders) the
// FOV spans the display window and the data window is a part of it.
PinholeCamera IntrinsicsOfFov(const SourceExr& exr, double fov_deg, bool of_display_window) {
  if (!of_display_window)
    return PinholeCamera::FromHorizontalFov(exr.width(), exr.height(), fov_deg);
  const SourceExr::Window& display = exr.display_window();
  PinholeCamera camera;
  camera.width = exr.width(), camera.height = exr.height();
  camera.fx = camera.fy =
      (display.width / 2.0) / std::tan(fov_deg * 3.14159265358979323846 / 360.0);
  camera.cx = display.min_x + display.width / 2.0 - exr.data_min_x();
  camera.cy = display.min_y + display.height / 2.0 - exr.data_min_y();
  return camera;
}

}  // namespace

void UeMrqImporter::ReadObjects(const fs::path& path) {
  const std::string file = path.string();
  const json root = ParseJsonFile(path);
  AtPointer(file, "/format", [&] {
    if (root.at("format").get<std::string>() != "lsds-ue-objects")
      throw Error("'format' must be \"lsds-ue-objects\"", Location(file, "/format"));
    return 0;
  });
  fps_ = AtPointer(file, "/fps", [&] { return root.value("fps", 24.0); });
  if (!(fps_ > 0)) throw Error("fps must be > 0", Location(file, "/fps"));
  sky_depth_cm_ = AtPointer(file, "/sky_depth_cm", [&] { return root.value("sky_depth_cm", 1e7); });
  std::set<uint32_t> class_ids;
  AtPointer(file, "/classes", [&] {
    for (size_t i = 0; i < root.at("classes").size(); ++i) {
      const json& c = root.at("classes").at(i);
      const std::string where = "/classes/" + std::to_string(i);
      ClassInfo info{
          AtPointer(file, where + "/id", [&] { return IdAt(c.at("id"), file, where + "/id"); }),
          AtPointer(file, where + "/name", [&] {
            return StringAt(c.at("name"), file, where + "/name");
          })};
      if (info.id == 0 || !class_ids.insert(info.id).second)
        throw Error("class ids must be > 0 and unique", Location(file, where + "/id"));
      classes_.push_back(info);
    }
    return 0;
  });
  std::set<uint32_t> instance_ids;
  AtPointer(file, "/actors", [&] {
    for (size_t i = 0; i < root.at("actors").size(); ++i) {
      const json& a = root.at("actors").at(i);
      const std::string where = "/actors/" + std::to_string(i);
      const std::string name = AtPointer(
          file, where + "/name", [&] { return StringAt(a.at("name"), file, where + "/name"); });
      Actor actor;
      actor.instance_id = AtPointer(file, where + "/instance_id", [&] {
        return IdAt(a.at("instance_id"), file, where + "/instance_id");
      });
      actor.class_id = AtPointer(file, where + "/class_id", [&] {
        return IdAt(a.at("class_id"), file, where + "/class_id");
      });
      if (actor.instance_id == 0 || !instance_ids.insert(actor.instance_id).second)
        throw Error("instance ids must be > 0 and unique", Location(file, where + "/instance_id"));
      if (!class_ids.count(actor.class_id))
        throw Error("class_id " + std::to_string(actor.class_id) + " is not in 'classes'",
                    Location(file, where + "/class_id"));
      if (!actors_.emplace(name, actor).second)
        throw Error("actor '" + name + "' listed twice", Location(file, where + "/name"));
      if (!a.contains("obb")) continue;  // not an object of interest
      ObjectIdentity target;
      target.instance_id = actor.instance_id;
      target.class_id = actor.class_id;
      target.name = a.value("object", name);
      target.asset = a.value("asset", "");
      target.obb = AtPointer(file, where + "/obb", [&] {
        const json& obb = a.at("obb");
        const json& r = obb.at("rotation");
        const Eigen::Vector3d extent = Vector3(obb.at("extent"));
        if (!(extent.minCoeff() >= 0))
          throw Error("extent must be >= 0", Location(file, where + "/obb/extent"));
        return EnuBoxOfUnrealBox(
            Vector3(obb.at("center")),
            extent,
            {r.at("pitch").get<double>(), r.at("yaw").get<double>(), r.at("roll").get<double>()});
      });
      targets_.push_back(target);
    }
    return 0;
  });
}

SourceDescription UeMrqImporter::Open(const fs::path& source, const ImportOptions& options) {
  if (!fs::is_directory(source))
    throw Error("a Movie Render Queue output folder was expected", Location(source.string()));
  root_.emplace(source, options.allow_links_outside);
  for (const fs::directory_entry& entry : fs::directory_iterator(source)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext != ".exr") continue;
    if (entry.is_directory()) continue;
    // A link out of the folder or a FIFO named .exr is refused, not skipped.
    FrameFile frame{root_->File(entry.path()), "", 0};
    if (!entry.is_regular_file()) continue;  // a dangling link
    if (!SplitFrameName(entry.path().stem().string(), &frame.sequence, &frame.number))
      throw Error(
          "EXR name has no frame number (MRQ names frames "
          "{sequence_name}.{frame_number})",
          Location(entry.path().string()));
    files_.push_back(frame);
  }
  if (files_.empty()) throw Error("no .exr frames in the folder", Location(source.string()));
  std::sort(files_.begin(), files_.end(), [](const auto& a, const auto& b) {
    return std::tie(a.sequence, a.number) < std::tie(b.sequence, b.number);
  });
  // Without a sidecar no pixel names an object: the layers are imported, the
  // ids are not.
  const fs::path objects =
      options.objects.empty() ? root_->File(source / kUeObjectsFile) : options.objects;
  if (!options.objects.empty() || fs::exists(objects))
    ReadObjects(objects);
  else
    warnings_.push_back(std::string("no ") + kUeObjectsFile +
                        " (give --objects): frames timed at 24 fps, no object named");
  fov_of_display_window_ = options.fov_window == "display";

  // The layout, from the first frame; every frame must have it.
  ReadLayout(SourceExr(files_.front().path));
  return Describe();
}

void UeMrqImporter::ReadLayout(const SourceExr& first) {
  width_ = first.width(), height_ = first.height();
  for (const char* prefix : {"", "FinalImage.", "rgba."}) {
    if (first.HasChannel(std::string(prefix) + "R") &&
        first.HasChannel(std::string(prefix) + "G") &&
        first.HasChannel(std::string(prefix) + "B")) {
      rgb_prefix_ = prefix;
      break;
    }
    if (std::string(prefix) == "rgba.")
      throw Error(
          "no final image channels (R, G, B, FinalImage.R, ... or "
          "rgba.R, ...)",
          Location(first.file()));
  }
  for (const std::string& channel : first.ChannelNames()) {
    // Unreal's name, and Nuke's spelling of the same channel.
    for (const char* suffix :
         {"WorldDepth.R", "SceneDepth.R", "WorldDepth.red", "SceneDepth.red"}) {
      const std::string s = suffix;
      if (channel.size() >= s.size() &&
          channel.compare(channel.size() - s.size(), s.size(), s) == 0 && depth_channel_.empty())
        depth_channel_ = channel;
    }
  }
  // No World Depth pass: the collection has no depth (the driver says so).
  const auto layers = ParseCryptomatteLayers(first.attributes(), first.file());
  for (const CryptomatteLayer& layer : layers) {
    if (layer.name.find("Actor") != std::string::npos || layers.size() == 1) id_layer_ = layer.name;
  }
  if (id_layer_.empty() && !layers.empty())
    throw Error(
        "several Cryptomatte layers and none of actors (cryptomatte/*/name "
        "containing 'Actor')",
        Location(first.file()));
  if (!id_layer_.empty()) {
    const std::optional<CryptomatteRankChannels> rank0 =
        FindRank0Channels(first.ChannelNames(), id_layer_);
    if (!rank0)
      throw Error("no rank-0 channels of Cryptomatte layer '" + id_layer_ + "' (" + id_layer_ +
                      "00.R/.G, .red/.green or .r/.g)",
                  Location(first.file()));
    id_channel_ = rank0->id, coverage_channel_ = rank0->coverage;
  }
  if (!id_layer_.empty() && actors_.empty())
    warnings_.push_back("the Cryptomatte layer '" + id_layer_ +
                        "' is not read: no actor of the sidecar names its pixels");
  const bool has_ids = !id_layer_.empty() && !actors_.empty();
  if (!has_ids) id_layer_.clear();
}

SourceDescription UeMrqImporter::Describe() const {
  SourceDescription description;
  description.classes = classes_;
  description.frame_count = static_cast<int64_t>(files_.size());
  description.semantics = {"rgb"};
  description.depth_kind = DepthKind::kPlanar;
  description.truth_origin = {{"rgb", "imported"}, {"camera", "imported"}};
  description.source_conventions = {
      {"world_frame", "unreal"},
      {"length_unit", "cm"},
      {"fov",
       std::string("unreal/camera/FinalImage/fov, horizontal, of the ") +
           (fov_of_display_window_ ? "display window (--fov-window display)"
                                   : "data window (the rendered image, overscan included)")},
      {"converted_to", "ENU m"}};
  if (!id_layer_.empty()) {
    description.semantics.insert(description.semantics.end(), {"classid", "instanceid"});
    description.truth_origin.insert(
        {{"instanceid", "imported"}, {"classid", "imported"}, {"obb", "imported"}});
    description.source_conventions["ids"] =
        "Cryptomatte layer " + id_layer_ + ", rank 0 (" + id_channel_ + ")";
  }
  if (!depth_channel_.empty()) {
    description.semantics.push_back("depth");
    description.truth_origin["depth"] = "imported";
    description.source_conventions["depth"] = "planar (SceneDepth), cm";
  }
  description.warnings = warnings_;
  return description;
}

SourceFrame UeMrqImporter::ReadFrame(int64_t index) {
  const FrameFile& frame_file = files_.at(static_cast<size_t>(index));
  const SourceExr exr(frame_file.path);
  const std::string& file = exr.file();
  if (exr.width() != width_ || exr.height() != height_)
    throw Error("frame " + std::to_string(index) + " is " + std::to_string(exr.width()) + "x" +
                    std::to_string(exr.height()) + ", the first frame " + std::to_string(width_) +
                    "x" + std::to_string(height_),
                Location(file));
  SourceFrame frame;
  if (index > 0) {
    const FrameFile& previous = files_.at(static_cast<size_t>(index - 1));
    if (previous.sequence != frame_file.sequence || previous.number + 1 != frame_file.number)
      shot_ = index;  // a new sequence or a gap: not flown continuously
  }
  frame.shot = shot_;
  frame.sequence = frame_file.sequence;
  frame.time = static_cast<double>(frame_file.number) / fps_;

  // Camera: horizontal FOV, location (cm), rotation (FRotator degrees).
  const double fov = exr.Number(LensKeys("fov"));
  if (!(fov > 0 && fov < 180))
    throw Error("horizontal fov " + std::to_string(fov) + " is not in (0, 180)", Location(file));
  frame.camera.intrinsics = IntrinsicsOfFov(exr, fov, fov_of_display_window_);
  const Eigen::Vector3d location(exr.Number(CameraKeys("curPos/x")),
                                 exr.Number(CameraKeys("curPos/y")),
                                 exr.Number(CameraKeys("curPos/z")));
  const UnrealRotator rotation{exr.Number(CameraKeys("curRot/pitch")),
                               exr.Number(CameraKeys("curRot/yaw")),
                               exr.Number(CameraKeys("curRot/roll"))};
  const Rigid3d cam_from_world = CamFromEnuOfUnrealCamera(location, rotation);
  SetCamFromWorld(cam_from_world, &frame.camera);

  // Final image.
  exr::FlatImage& rgb = frame.flat["rgb"] = exr::FlatImage(width_, height_);
  for (const char* c : {"R", "G", "B"})
    rgb.AddChannel(c, exr::PixelType::kHalf).floats = exr.ReadFloat(rgb_prefix_ + c);

  if (!depth_channel_.empty()) ReadDepth(exr, &frame);
  if (!id_layer_.empty()) ReadIds(exr, index, &frame);
  return frame;
}

void UeMrqImporter::ReadDepth(const SourceExr& exr, SourceFrame* frame) const {
  const std::string& file = exr.file();
  // Depth: planar cm -> m; the sky (beyond sky_depth_cm) -> +inf.
  exr::FlatImage& depth = frame->flat["depth"] = exr::FlatImage(width_, height_);
  std::vector<float>& z = depth.AddChannel("Z", exr::PixelType::kFloat).floats;
  z = exr.ReadFloat(depth_channel_);
  for (float& value : z) {
    if (std::isnan(value) || value < 0)
      throw Error("depth channel '" + depth_channel_ + "' holds a negative or NaN value",
                  Location(file));
    value = (std::isinf(value) || value >= sky_depth_cm_) ? std::numeric_limits<float>::infinity()
                                                          : static_cast<float>(value * 0.01);
  }
}

void UeMrqImporter::ReadIds(const SourceExr& exr, int64_t index, SourceFrame* frame) const {
  const std::string& file = exr.file();
  // Ids: the rank-0 Cryptomatte id (the largest coverage) of each pixel.
  const auto layers = ParseCryptomatteLayers(exr.attributes(), file);
  const auto layer =
      std::find_if(layers.begin(), layers.end(), [&](auto& l) { return l.name == id_layer_; });
  if (layer == layers.end())
    throw Error("no Cryptomatte layer '" + id_layer_ + "' in the header", Location(file));
  const std::string& id_channel = id_channel_;
  if (exr.ChannelType(id_channel) != exr::PixelType::kFloat)
    throw Error("Cryptomatte channel '" + id_channel +
                    "' is missing or not 32-bit float (ids are hashes stored "
                    "bit for bit)",
                Location(file));
  const std::vector<float> ids = exr.ReadFloat(id_channel);
  const std::vector<float> coverage = exr.ReadFloat(coverage_channel_);
  exr::FlatImage& instances = frame->flat["instanceid"] = exr::FlatImage(width_, height_);
  exr::FlatImage& classes = frame->flat["classid"] = exr::FlatImage(width_, height_);
  std::vector<uint32_t>& instance = instances.AddChannel("id", exr::PixelType::kUint).uints;
  std::vector<uint32_t>& klass = classes.AddChannel("id", exr::PixelType::kUint).uints;
  for (size_t p = 0; p < ids.size(); ++p) {
    uint32_t bits;
    std::memcpy(&bits, &ids[p], sizeof bits);
    if (bits == 0 || !(coverage[p] > 0)) continue;  // nothing: background
    const auto named = layer->names_by_bits.find(bits);
    if (named == layer->names_by_bits.end()) {
      Location where =
          Location::Pixel(file, index, static_cast<int>(p % width_), static_cast<int>(p / width_));
      throw Error("Cryptomatte id in '" + id_channel + "' is not in the layer's manifest", where);
    }
    const auto actor = actors_.find(named->second);
    if (actor == actors_.end()) continue;  // not listed: background
    instance[p] = actor->second.instance_id;
    klass[p] = actor->second.class_id;
  }
  frame->targets = targets_;
}

}  // namespace lsds::import
