#include "validators/frame_checks.h"

#include <cmath>

#include "libs/collection/bundle_layout.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/motion_layout.h"
#include "libs/collection/worldposition_layout.h"
#include "validators/frame_checker.h"

namespace lsds::validate {

namespace detail {

FrameOutcome FrameChecker::Run() {
  width_ = frame_.camera.intrinsics.width;
  height_ = frame_.camera.intrinsics.height;
  {
    // Decoding serves every layer check; it is charged to layer.readable.
    CheckTimer timer(&outcome_.check_seconds, Chosen({"layer.readable"}));
    LoadLayers();
  }
  CheckValues();  // times each check's block itself
  CheckBundle();  // idem
  {
    CheckTimer timer(&outcome_.check_seconds,
                     Chosen({"cross.bbox-tight",
                             "cross.visible-pixels",
                             "cross.class-instance",
                             "cross.obb-contains-bbox",
                             "cross.oriented-box"}));
    CheckObjects();
  }
  {
    CheckTimer timer(&outcome_.check_seconds, Chosen({"cross.worldpos-depth"}));
    CheckWorldPositionVsDepth();
  }
  {
    CheckTimer timer(&outcome_.check_seconds,
                     Chosen({"cross.motion-pose", "cross.motion-invalid"}));
    CheckMotion();
  }
  {
    std::vector<std::string> camera;
    for (const CheckInfo& check : AllChecks()) {
      if (check.id.rfind("camera.", 0) == 0) camera.push_back(check.id);
    }
    CheckTimer timer(&outcome_.check_seconds, Chosen(std::move(camera)));
    CheckCamera();
  }
  return std::move(outcome_);
}

namespace {

bool IsIdSemantic(const std::string& semantic) {
  return semantic == "classid" || semantic == "instanceid";
}

}  // namespace

bool FrameChecker::CheckHeader(const LayerInfo& layer,
                               const std::string& file,
                               const fs::path& path) {
  exr::ExrInfo info;
  try {
    info = exr::ReadExrInfo(path);
  } catch (const std::exception& e) {
    Emit("layer.readable", FileLocation(file), std::string("cannot open: ") + e.what());
    return false;
  }
  // Compact and residual bundles yield channels they do not store; residual
  // worldposition and motion yield X, Y[, Z] from their stored dX, dY[, dZ].
  const bool residual =
      layer.semantic == "motion" ? IsResidualMotion(info) : IsResidualWorldPosition(info);
  info.channels = layer.semantic == "motion" ? ReadableMotionChannels(info)
                                             : ReadableWorldPositionChannels(info);
  info.channels = ReadableChannels(info);
  bool ok = true;
  if ((layer.semantic == "worldposition" || layer.semantic == "motion") &&
      (layer.flat_layout == FlatLayout::kResidual) != residual) {
    // Readers follow the file, so the values are right; the table is wrong.
    Emit("layer.channels",
         FileLocation(file),
         std::string("is stored in the ") + (residual ? "residual" : "float") +
             " layout but layer '" + layer.name + "' declares layout '" +
             FlatLayoutName(layer.flat_layout) + "'");
  }
  if (layer.semantic == "motion" && residual) CheckMotionReference(info, file, path);
  if (info.deep != layer.deep) {
    Emit("layer.channels",
         FileLocation(file),
         std::string("file is ") + (info.deep ? "deep" : "flat") + " but layer '" + layer.name +
             "' is declared " + (layer.deep ? "deep" : "flat"));
    ok = false;
  }
  if (info.width != width_ || info.height != height_) {
    Emit("layer.dimensions",
         FileLocation(file),
         "is " + std::to_string(info.width) + "x" + std::to_string(info.height) +
             " but the frame's camera is " + std::to_string(width_) + "x" +
             std::to_string(height_));
    ok = false;
  }
  for (const LayerChannel& declared : layer.channels) {
    const exr::ChannelSpec* found = info.Find(declared.name);
    if (found == nullptr) {
      Emit("layer.channels",
           FileLocation(file),
           "has no channel '" + declared.name + "' declared by layer '" + layer.name + "'");
      ok = false;
    } else if (found->type != declared.type) {
      const bool id_channel =
          IsIdSemantic(layer.semantic) ||
          (layer.semantic == "bundle" && declared.type == exr::PixelType::kUint);
      Emit(id_channel ? "layer.id-type" : "layer.channels",
           FileLocation(file),
           "channel '" + declared.name + "' is " + exr::PixelTypeName(found->type) +
               " but declared " + exr::PixelTypeName(declared.type));
      ok = false;
    }
  }
  for (const exr::ChannelSpec& present : info.channels) {
    if (layer.FindChannel(present.name) == nullptr) {
      Emit("layer.channels",
           FileLocation(file),
           "has channel '" + present.name + "' that layer '" + layer.name + "' does not declare");
    }
  }
  if ((IsIdSemantic(layer.semantic)) && !layer.channels.empty() &&
      layer.channels[0].type != exr::PixelType::kUint) {
    Emit("layer.id-type",
         FileLocation(file),
         "id layer '" + layer.name + "' is declared " + exr::PixelTypeName(layer.channels[0].type) +
             ", ids must be uint");
    ok = false;
  }
  return ok;
}

// A residual motion file decodes against the previous camera its header
// names: a file measured against another frame (or none) would read as that
// frame's motion, so the camera must be the one collection.json says came
// before.
void FrameChecker::CheckMotionReference(const exr::ExrInfo& info,
                                        const std::string& file,
                                        const fs::path& path) {
  if (!Selected("layer.motion-reference")) return;
  std::optional<CameraTruth> reference;
  try {
    reference = ResidualMotionReference(info, path);
  } catch (const std::exception& e) {
    Emit("layer.motion-reference", FileLocation(file), e.what());
    return;
  }
  const std::optional<CameraTruth>& expected = input_.previous_camera;
  if (!reference || !expected) {
    if (reference.has_value() != expected.has_value()) {
      Emit("layer.motion-reference",
           FileLocation(file),
           reference ? "names a previous camera, but the frame has no previous frame in its shot"
                     : "names no previous camera (\"none\"), but the frame continues a shot");
    }
    return;
  }
  const PinholeCamera &a = reference->intrinsics, &b = expected->intrinsics;
  auto close = [](double x, double y) {
    return std::abs(x - y) <= 1e-9 * std::max({1.0, std::abs(x), std::abs(y)});
  };
  bool same = a.width == b.width && a.height == b.height && close(a.fx, b.fx) &&
              close(a.fy, b.fy) && close(a.cx, b.cx) && close(a.cy, b.cy);
  for (int i = 0; i < 9 && same; ++i)
    same = close(reference->cam_from_world_rotation(i / 3, i % 3),
                 expected->cam_from_world_rotation(i / 3, i % 3));
  for (int i = 0; i < 3 && same; ++i)
    same = close(reference->cam_from_world_translation[i], expected->cam_from_world_translation[i]);
  if (!same) {
    const Eigen::Vector3d at =
        -reference->cam_from_world_rotation.transpose() * reference->cam_from_world_translation;
    const Eigen::Vector3d want =
        -expected->cam_from_world_rotation.transpose() * expected->cam_from_world_translation;
    Emit("layer.motion-reference",
         FileLocation(file),
         "was measured against a camera at (" + Fmt(at.x()) + ", " + Fmt(at.y()) + ", " +
             Fmt(at.z()) + "), not the previous frame's camera at (" + Fmt(want.x()) + ", " +
             Fmt(want.y()) + ", " + Fmt(want.z()) + ") (or other intrinsics or orientation)");
  }
}

void FrameChecker::LoadLayers() {
  const CheckSelection& c = *context_.checks;
  const bool need_flat = c.HasGroup("layer") || c.HasGroup("cross") || c.HasGroup("camera") ||
                         c.Has("stats.class-unused");
  const bool need_bundle = c.Has("layer.bundle") || c.Has("cross.bundle-centre");
  const bool need_headers = need_flat || need_bundle;
  if (!need_headers) return;
  for (const LayerInfo& layer : header_.layers) {
    const auto it = frame_.files.find(layer.name);
    if (it == frame_.files.end()) continue;  // structure.missing-file, reported while streaming
    const fs::path path = context_.root / it->second;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) continue;  // idem
    if (!CheckHeader(layer, it->second, path)) continue;
    const bool first_of_semantic = file_of_.count(layer.semantic) == 0;
    if (layer.deep ? !need_bundle : !need_flat) continue;
    if (!first_of_semantic || layer.semantic == "derived") continue;
    std::vector<std::string> channels;
    for (const LayerChannel& channel : layer.channels) channels.push_back(channel.name);
    try {
      if (layer.deep) {
        if (layer.semantic != "bundle") continue;
        bundle_ = ReadBundleExr(path, channels);  // either bundle layout
      } else {
        flat_[layer.semantic] = ReadFlatLayerFile(  // any layout
            path,
            layer.semantic,
            channels,
            [&](const std::string& depth_layer) {
              // The depth this frame already decoded, else its file.
              const LayerInfo* depth = Layer("depth");
              const FlatImage* decoded = Flat("depth");
              if (depth != nullptr && depth->name == depth_layer && decoded != nullptr) {
                return PredictionFromDepth(*decoded, *depth, frame_.camera);
              }
              return PredictionOfFrame(context_.root, header_, frame_, depth_layer);
            });
      }
      file_of_[layer.semantic] = it->second;
      ++outcome_.files_decoded;
      outcome_.bytes_decoded += static_cast<int64_t>(fs::file_size(path, ec));
    } catch (const std::exception& e) {
      Emit("layer.readable", FileLocation(it->second), std::string("cannot decode: ") + e.what());
    }
  }
}

}  // namespace detail

FrameOutcome CheckFrame(const FrameCheckContext& context, const FrameInput& input) {
  return detail::FrameChecker(context, input).Run();
}

}  // namespace lsds::validate
