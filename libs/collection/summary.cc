#include "libs/collection/summary.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <sstream>

#include "libs/collection/collection_read_once.h"
#include "libs/collection/file_sizes.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/exr_info.h"
#include "libs/geometry/world_frame.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "libs/util/text_check.h"

namespace lsds {

namespace fs = std::filesystem;

std::string LayerLayoutName(const LayerInfo& layer) {
  if (layer.deep) return BundleLayoutName(layer.layout);
  if (layer.semantic == "worldposition" || layer.semantic == "motion")
    return FlatLayoutName(layer.flat_layout);
  return "";
}

namespace {

// "name:type,..." of `channels` (declared or stored).
template <typename Channel>
std::vector<std::string> ChannelNames(const std::vector<Channel>& channels) {
  std::vector<std::string> names;
  names.reserve(channels.size());
  for (const Channel& c : channels) names.push_back(c.name + ":" + exr::PixelTypeName(c.type));
  return names;
}

// The stored channels of `layer` (its first readable file's header).
void ReadStoredChannels(const fs::path& file, LayerSummary* ls) {
  try {
    ls->stored_channels = exr::ReadExrInfo(file).channels;
    ls->stored_error.clear();
  } catch (const Error& e) {
    ls->stored_error = e.what();
  }
}

}  // namespace

namespace {

// The summary of the collection at `root` whose header is `header` and whose
// frames `for_each_frame` streams.
CollectionSummary Summarize(const fs::path& root,
                            const CollectionHeader& header,
                            const ForEachFrameFn& for_each_frame) {
  CollectionSummary s;
  const WorldFrame& world = header.conventions.world;
  std::error_code ec;
  s.collection_json_bytes = static_cast<int64_t>(fs::file_size(root / kCollectionFile, ec));
  std::vector<LayerSummary*> layer_summaries;  // in the order of header.layers
  for (const LayerInfo& layer : header.layers) layer_summaries.push_back(&s.layers[layer.name]);
  for (const ClassInfo& c : header.classes) s.classes[c.id];
  FileSizes file_sizes(root);
  for_each_frame([&](const Frame& frame) {
    const PinholeCamera& k = frame.camera.intrinsics;
    const double hfov = k.HorizontalFovDeg();
    const Rigid3d cam_from_enu = world.CamFromEnuMetres(frame.camera.cam_from_world_rotation,
                                                        frame.camera.cam_from_world_translation);
    const double height = CameraCenterInWorld(cam_from_enu).z() / world.metres_per_unit;
    if (s.frames == 0) {
      s.time_min = s.time_max = frame.time;
      s.hfov_min_deg = s.hfov_max_deg = hfov;
      s.camera_height_min = s.camera_height_max = height;
    }
    s.time_min = std::min(s.time_min, frame.time);
    s.time_max = std::max(s.time_max, frame.time);
    s.hfov_min_deg = std::min(s.hfov_min_deg, hfov);
    s.hfov_max_deg = std::max(s.hfov_max_deg, hfov);
    s.camera_height_min = std::min(s.camera_height_min, height);
    s.camera_height_max = std::max(s.camera_height_max, height);
    s.resolutions[std::to_string(k.width) + "x" + std::to_string(k.height)]++;
    if (frame.rig_camera) s.rig_frames[*frame.rig_camera]++;
    for (size_t l = 0; l < header.layers.size(); ++l) {
      LayerSummary& ls = *layer_summaries[l];
      const auto it = frame.files.find(header.layers[l].name);
      const std::optional<uintmax_t> size =
          it == frame.files.end() ? std::nullopt : file_sizes.Size(it->second);
      if (!size) {
        ++ls.missing_files;
      } else {
        ++ls.files;
        ls.bytes += static_cast<int64_t>(*size);
        if (ls.stored_channels.empty()) ReadStoredChannels(root / it->second, &ls);
      }
    }
    for (const ObjectTruth& object : frame.objects) {
      ClassSummary& cs = s.classes[object.class_id];
      ++cs.objects;
      cs.instance_ids.insert(object.instance_id);
      ++s.objects;
    }
    ++s.frames;
  });
  s.total_bytes = s.collection_json_bytes;
  for (const auto& [name, layer] : s.layers) s.total_bytes += layer.bytes;
  for (const MetadataVariant& variant : header.metadata) {
    s.total_bytes += static_cast<int64_t>(fs::file_size(root / variant.file, ec));
    if (ec) ec.clear();
  }
  return s;
}

}  // namespace

CollectionInfo SummarizeCollection(const fs::path& root) {
  CollectionInfo info{root, {}, {}};
  info.header = ReadCollectionOnce(
      root, [&](const CollectionHeader& header, const ForEachFrameFn& for_each_frame) {
        info.summary = Summarize(root, header, for_each_frame);
      });
  return info;
}

nlohmann::json SummaryToJson(const CollectionInfo& info) {
  const CollectionHeader& h = info.header;
  const CollectionSummary& s = info.summary;
  nlohmann::json layers = nlohmann::json::array();
  for (const LayerInfo& layer : h.layers) {
    const LayerSummary& ls = s.layers.at(layer.name);
    // `channels`: what the files store; `read_as`: what every lsds reader
    // yields (the layer table's channels; they differ in the residual layouts).
    nlohmann::json entry = {{"name", layer.name},
                            {"semantic", layer.semantic},
                            {"deep", layer.deep},
                            {"channels", ChannelNames(ls.stored_channels)},
                            {"read_as", ChannelNames(layer.channels)},
                            {"files", ls.files},
                            {"missing_files", ls.missing_files},
                            {"bytes", ls.bytes}};
    if (!ls.stored_error.empty()) entry["channels_error"] = ls.stored_error;
    if (const std::string layout = LayerLayoutName(layer); !layout.empty())
      entry["layout"] = layout;
    if (layer.depth_kind) entry["depth_kind"] = DepthKindName(*layer.depth_kind);
    layers.push_back(entry);
  }
  nlohmann::json classes = nlohmann::json::array();
  for (const auto& [id, cs] : s.classes) {
    const ClassInfo* info = h.FindClass(id);
    classes.push_back({{"id", id},
                       {"name", info ? info->name : std::string("(not in class table)")},
                       {"objects", cs.objects},
                       {"instances", cs.instance_ids.size()}});
  }
  nlohmann::json rig = nullptr;
  if (h.rig) {
    rig = nlohmann::json::array();
    for (const RigCamera& c : h.rig->cameras) {
      // + 0: no "-0" in print.
      const Eigen::Vector3d centre = c.cam_from_rig.Inverse().translation + Eigen::Vector3d::Zero();
      rig.push_back(
          {{"name", c.name},
           {"resolution",
            std::to_string(c.intrinsics.width) + "x" + std::to_string(c.intrinsics.height)},
           {"hfov_deg", c.intrinsics.HorizontalFovDeg()},
           {"position_in_rig", {centre.x(), centre.y(), centre.z()}},
           {"frames", s.rig_frames.count(c.name) ? s.rig_frames.at(c.name) : 0}});
    }
  }
  return {{"path", Utf8Escaped(info.root.string())},
          {"format_version", h.format_version},
          {"generator", h.provenance.generator + " " + h.provenance.generator_version},
          {"frames", s.frames},
          {"frame_count_declared", h.frame_count},
          {"time", {{"min", s.time_min}, {"max", s.time_max}}},
          {"units",
           {{"world_frame", h.conventions.world.name},
            {"length_unit", h.conventions.world.length_unit}}},
          {"cameras",
           {{"resolutions", s.resolutions},
            {"hfov_deg", {{"min", s.hfov_min_deg}, {"max", s.hfov_max_deg}}},
            {"height", {{"min", s.camera_height_min}, {"max", s.camera_height_max}}},
            {"rig", rig}}},
          {"layers", layers},
          {"classes", classes},
          {"objects", s.objects},
          {"metadata_variants", h.metadata.size()},
          {"bytes", s.total_bytes}};
}

std::string SummaryToText(const CollectionInfo& info) {
  const CollectionHeader& h = info.header;
  const CollectionSummary& s = info.summary;
  std::ostringstream out;
  out << "collection  " << info.root.string() << "  (format " << h.format_version << ", "
      << h.provenance.generator << " " << h.provenance.generator_version << ")\n";
  out << "frames      " << s.frames;
  if (s.frames != h.frame_count) out << "  (header declares " << h.frame_count << ")";
  out << ", time " << s.time_min << " .. " << s.time_max << " s\n";
  out << "units       world " << h.conventions.world.name << ", " << h.conventions.world.length_unit
      << ", " << (h.conventions.world.right_handed() ? "right" : "left")
      << "-handed; camera OpenCV\n";
  out << "cameras     ";
  for (const auto& [resolution, count] : s.resolutions)
    out << resolution << " (" << count << " frames) ";
  char line[160];
  std::snprintf(line,
                sizeof(line),
                "hfov %.2f..%.2f deg, height %.2f..%.2f %s\n",
                s.hfov_min_deg,
                s.hfov_max_deg,
                s.camera_height_min,
                s.camera_height_max,
                h.conventions.world.length_unit.c_str());
  out << line;
  if (h.rig) {
    out << "rig         ";
    for (const RigCamera& c : h.rig->cameras) {
      // + 0: no "-0" in print.
      const Eigen::Vector3d centre = c.cam_from_rig.Inverse().translation + Eigen::Vector3d::Zero();
      const auto frames = s.rig_frames.find(c.name);
      std::snprintf(line,
                    sizeof(line),
                    "%s %dx%d at (%.3g, %.3g, %.3g) (%lld frames)  ",
                    c.name.c_str(),
                    c.intrinsics.width,
                    c.intrinsics.height,
                    centre.x(),
                    centre.y(),
                    centre.z(),
                    static_cast<long long>(frames == s.rig_frames.end() ? 0 : frames->second));
      out << line;
    }
    out << "\n";
  }
  out << "layers\n";
  for (const LayerInfo& layer : h.layers) {
    const LayerSummary& ls = s.layers.at(layer.name);
    const std::string stored = Join(ChannelNames(ls.stored_channels), ",");
    std::snprintf(line,
                  sizeof(line),
                  "  %-14s %-5s %-44s %6lld files %10s",
                  layer.name.c_str(),
                  layer.deep ? "deep" : "flat",
                  stored.empty() ? "(no readable file)" : stored.c_str(),
                  static_cast<long long>(ls.files),
                  FormatBytes(static_cast<double>(ls.bytes)).c_str());
    out << line;
    if (layer.depth_kind) out << "  " << DepthKindName(*layer.depth_kind);
    if (const std::string layout = LayerLayoutName(layer); !layout.empty()) {
      out << "  layout " << layout;
      // EXR stores channels sorted by name: compare as sets.
      std::vector<std::string> read_as = ChannelNames(layer.channels);
      std::vector<std::string> stored_sorted = ChannelNames(ls.stored_channels);
      std::vector<std::string> read_as_sorted = read_as;
      std::sort(stored_sorted.begin(), stored_sorted.end());
      std::sort(read_as_sorted.begin(), read_as_sorted.end());
      if (read_as_sorted != stored_sorted) out << ", read as " << Join(read_as, ",");
    }
    if (ls.missing_files > 0) out << "  MISSING " << ls.missing_files;
    out << "\n";
  }
  out << "classes\n";
  for (const auto& [id, cs] : s.classes) {
    const ClassInfo* info = h.FindClass(id);
    std::snprintf(line,
                  sizeof(line),
                  "  %4u %-20s %8lld objects %6zu instances\n",
                  id,
                  info ? info->name.c_str() : "(not in class table)",
                  static_cast<long long>(cs.objects),
                  cs.instance_ids.size());
    out << line;
  }
  out << "metadata    " << h.metadata.size() << " variant(s)\n";
  out << "total       " << FormatBytes(static_cast<double>(s.total_bytes)) << "\n";
  return out.str();
}

}  // namespace lsds
