#include "validators/frame_checks.h"

#include "libs/util/strings.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

#include "libs/collection/bundle_layout.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/motion_layout.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/exr_info.h"
#include "libs/exr/flat_image.h"
#include "libs/geometry/instance_mask.h"
#include "libs/geometry/oriented_box.h"
#include "libs/geometry/oriented_box2d.h"
#include "validators/camera_checks.h"

namespace lsds::validate {

namespace fs = std::filesystem;
using exr::DeepImage;
using exr::FlatImage;

namespace {

// Counts the pixels that fail one check in one file and remembers the first, so
// that a layer full of NaN is one finding ("40000 pixels ..., first at ...")
// and not 40000.
struct PixelTally {
  int64_t count = 0;
  int x = -1, y = -1;
  std::string first_detail;
  void Add(int px, int py, const std::string& detail = "") {
    if (count++ == 0) {
      x = px, y = py;
      first_detail = detail;
    }
  }
};

std::string Fmt(double v) { return FormatNumber(v); }

std::string PointText(const Eigen::Vector2d& p) {
  return "(" + Fmt(p.x()) + ", " + Fmt(p.y()) + ")";
}

// Why `box` is not a rectangle with clockwise corners on the image (y down),
// or "" when it is. Sides may have zero length (the amodal box of an OBB seen
// edge-on); tolerances are 1e-6 relative to the box's size.
std::string RectangleProblem(const OrientedBox2d& box) {
  const auto& c = box.corners;
  for (const Eigen::Vector2d& corner : c)
    if (!corner.allFinite()) return "a corner is not finite";
  const double size = std::max(1.0, (c[2] - c[0]).norm());
  if ((c[0] + c[2] - c[1] - c[3]).norm() > 1e-6 * size)
    return "its corners are not a parallelogram (corner 3 is not corner 0 + corner 2 - corner 1)";
  const Eigen::Vector2d side_a = c[1] - c[0], side_b = c[2] - c[1];
  if (std::abs(side_a.dot(side_b)) > 1e-6 * size * size) return "its sides are not perpendicular";
  // The z of side_a x side_b: positive when the turn is clockwise as seen on
  // the image, y pointing down.
  if (side_a.x() * side_b.y() - side_a.y() * side_b.x() < -1e-6 * size * size)
    return "its corners run counter-clockwise on the image";
  return "";
}

class FrameChecker {
 public:
  FrameChecker(const FrameCheckContext& context, const FrameInput& input)
      : context_(context), input_(input), frame_(input.frame), header_(*context.header) {}

  FrameOutcome Run();

 private:
  bool Selected(const std::string& id) const { return context_.checks->Has(id); }
  // The selected ones of `ids` (a block's time is charged to them).
  std::vector<std::string> Chosen(std::vector<std::string> ids) const {
    ids.erase(std::remove_if(
                  ids.begin(), ids.end(), [&](const std::string& id) { return !Selected(id); }),
              ids.end());
    return ids;
  }
  void Emit(const std::string& id,
            Location location,
            const std::string& message,
            const std::string& object = "") {
    if (!Selected(id)) return;
    outcome_.findings.push_back({GetCheck(id).severity, id, std::move(location), object, message});
  }
  Location FileLocation(const std::string& file) const {
    Location where(file);
    where.frame = frame_.index;
    return where;
  }
  Location JsonLocation(const std::string& pointer_suffix) const {
    Location where(kCollectionFile, "/frames/" + std::to_string(input_.position) + pointer_suffix);
    where.frame = frame_.index;
    return where;
  }
  void EmitTally(const std::string& id,
                 const std::string& file,
                 const PixelTally& tally,
                 const std::string& what) {
    if (tally.count == 0) return;
    std::string message = std::to_string(tally.count) + " pixel(s) " + what;
    if (!tally.first_detail.empty()) message += "; first: " + tally.first_detail;
    Emit(id, Location::Pixel(file, frame_.index, tally.x, tally.y), message);
  }

  void LoadLayers();
  bool CheckHeader(const LayerInfo& layer, const std::string& file, const fs::path& path);
  void CheckMotionReference(const exr::ExrInfo& info,
                            const std::string& file,
                            const fs::path& path);
  void CheckValues();
  void CheckBundle();
  void CheckObjects();
  void CheckOrientedBoxes(const ObjectTruth& object,
                          const std::string& pointer,
                          const std::string& who,
                          const InstanceMask& extent);
  void CheckWorldPositionVsDepth();
  void CheckMotion();
  void CheckCamera();

  const FlatImage* Flat(const std::string& semantic) const {
    const auto it = flat_.find(semantic);
    return it == flat_.end() ? nullptr : &it->second;
  }
  const LayerInfo* Layer(const std::string& semantic) const {
    return header_.FindLayerBySemantic(semantic);
  }
  std::string FileOf(const std::string& semantic) const {
    const auto it = file_of_.find(semantic);
    return it == file_of_.end() ? std::string() : it->second;
  }
  // The first declared channel of the layer for `semantic`, if it was decoded.
  const std::vector<float>* Channel(const std::string& semantic, size_t k) const {
    const FlatImage* image = Flat(semantic);
    const LayerInfo* layer = Layer(semantic);
    if (image == nullptr || layer == nullptr || k >= layer->channels.size()) return nullptr;
    const exr::FlatChannel* channel = image->Find(layer->channels[k].name);
    if (channel == nullptr || channel->floats.size() != image->pixel_count()) return nullptr;
    return &channel->floats;
  }
  const std::vector<uint32_t>* Ids(const std::string& semantic) const {
    const FlatImage* image = Flat(semantic);
    const LayerInfo* layer = Layer(semantic);
    if (image == nullptr || layer == nullptr || layer->channels.empty()) return nullptr;
    const exr::FlatChannel* channel = image->Find(layer->channels[0].name);
    if (channel == nullptr || channel->uints.size() != image->pixel_count()) return nullptr;
    return &channel->uints;
  }

  const FrameCheckContext& context_;
  const FrameInput& input_;
  const Frame& frame_;
  const CollectionHeader& header_;
  FrameOutcome outcome_;
  std::map<std::string, FlatImage> flat_;  // by semantic (the first layer of each semantic)
  std::optional<DeepImage> bundle_;
  std::map<std::string, std::string> file_of_;  // semantic -> file relative to the root
  int width_ = 0, height_ = 0;
};

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

bool IsIdSemantic(const std::string& semantic) {
  return semantic == "classid" || semantic == "instanceid";
}

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

void FrameChecker::CheckValues() {
  const size_t n = static_cast<size_t>(width_) * height_;
  auto xy = [&](size_t p, int* x, int* y) {
    *x = static_cast<int>(p % width_);
    *y = static_cast<int>(p / width_);
  };
  if (const LayerInfo* layer = Layer("rgb"); layer && Flat("rgb") && Selected("layer.rgb-range")) {
    CheckTimer timer(&outcome_.check_seconds, {"layer.rgb-range"});
    PixelTally bad;
    for (size_t k = 0; k < layer->channels.size(); ++k) {
      const std::vector<float>* v = Channel("rgb", k);
      if (v == nullptr) continue;
      for (size_t p = 0; p < n; ++p) {
        const float value = (*v)[p];
        if (!(std::isfinite(value) && value >= 0)) {
          int x, y;
          xy(p, &x, &y);
          bad.Add(x, y, layer->channels[k].name + " = " + Fmt(value));
        }
      }
    }
    EmitTally("layer.rgb-range", FileOf("rgb"), bad, "with non-finite or negative colour");
  }
  if (const std::vector<float>* z = Channel("depth", 0); z && Selected("layer.depth-finite")) {
    CheckTimer timer(&outcome_.check_seconds, {"layer.depth-finite"});
    PixelTally bad;
    for (size_t p = 0; p < n; ++p) {
      const float d = (*z)[p];
      if (std::isnan(d) || d < 0 || d == -INFINITY) {
        int x, y;
        xy(p, &x, &y);
        bad.Add(x, y, "depth = " + Fmt(d));
      }
    }
    EmitTally("layer.depth-finite",
              FileOf("depth"),
              bad,
              "with NaN or negative depth (only +inf, for sky, is allowed "
              "beside finite >= 0)");
  }
  if (Flat("normal") && Selected("layer.normal-unit")) {
    CheckTimer timer(&outcome_.check_seconds, {"layer.normal-unit"});
    const auto *nx = Channel("normal", 0), *ny = Channel("normal", 1), *nz = Channel("normal", 2);
    if (nx && ny && nz) {
      PixelTally bad;
      for (size_t p = 0; p < n; ++p) {
        const double a = (*nx)[p], b = (*ny)[p], c = (*nz)[p];
        const double length = std::sqrt(a * a + b * b + c * c);
        if (length == 0) continue;  // sky
        if (!(std::abs(length - 1) <= 1e-3)) {
          int x, y;
          xy(p, &x, &y);
          bad.Add(x, y, "|n| = " + Fmt(length));
        }
      }
      EmitTally("layer.normal-unit", FileOf("normal"), bad, "with a normal of length != 1");
    }
  }
  if (Flat("worldposition") && Selected("layer.worldposition-finite")) {
    CheckTimer timer(&outcome_.check_seconds, {"layer.worldposition-finite"});
    const auto *px = Channel("worldposition", 0), *py = Channel("worldposition", 1),
               *pz = Channel("worldposition", 2);
    if (px && py && pz) {
      PixelTally bad;
      for (size_t p = 0; p < n; ++p) {
        const float a = (*px)[p], b = (*py)[p], c = (*pz)[p];
        const bool finite = std::isfinite(a) && std::isfinite(b) && std::isfinite(c);
        const bool sky = a == INFINITY && b == INFINITY && c == INFINITY;
        if (!finite && !sky) {
          int x, y;
          xy(p, &x, &y);
          bad.Add(x, y, "(" + Fmt(a) + ", " + Fmt(b) + ", " + Fmt(c) + ")");
        }
      }
      EmitTally("layer.worldposition-finite",
                FileOf("worldposition"),
                bad,
                "with a non-finite world position that is not sky (+inf, +inf, "
                "+inf)");
    }
  }
  if (const LayerInfo* layer = Layer("shadow");
      layer && Flat("shadow") && Selected("layer.shadow-range")) {
    CheckTimer timer(&outcome_.check_seconds, {"layer.shadow-range"});
    PixelTally bad;
    for (size_t k = 0; k < layer->channels.size(); ++k) {
      const std::vector<float>* v = Channel("shadow", k);
      if (v == nullptr) continue;
      for (size_t p = 0; p < n; ++p) {
        const float value = (*v)[p];
        if (!(value >= 0 && value <= 1)) {
          int x, y;
          xy(p, &x, &y);
          bad.Add(x, y, layer->channels[k].name + " = " + Fmt(value));
        }
      }
    }
    EmitTally("layer.shadow-range", FileOf("shadow"), bad, "outside [0, 1]");
  }
  // Motion may exceed [0, 1] (motion beyond one image size); NaN marks a pixel
  // with no valid motion and must be NaN on both channels.
  if (Flat("motion") && Selected("layer.motion-range")) {
    CheckTimer timer(&outcome_.check_seconds, {"layer.motion-range"});
    const auto *mx = Channel("motion", 0), *my = Channel("motion", 1);
    if (mx && my) {
      PixelTally bad;
      for (size_t p = 0; p < n; ++p) {
        const float a = (*mx)[p], b = (*my)[p];
        const bool valid = std::isfinite(a) && std::isfinite(b);
        const bool invalid = std::isnan(a) && std::isnan(b);
        if (!valid && !invalid) {
          int x, y;
          xy(p, &x, &y);
          bad.Add(x, y, "(" + Fmt(a) + ", " + Fmt(b) + ")");
        }
      }
      EmitTally("layer.motion-range",
                FileOf("motion"),
                bad,
                "whose motion is neither finite nor NaN on both channels");
    }
  }
  if (const std::vector<uint32_t>* ids = Ids("classid")) {
    CheckTimer timer(&outcome_.check_seconds, Chosen({"layer.classid-known"}));
    PixelTally bad;
    uint32_t last_known = 0;
    for (size_t p = 0; p < n; ++p) {
      const uint32_t id = (*ids)[p];
      if (id == 0 || id == last_known) continue;
      if (header_.FindClass(id) != nullptr) {
        last_known = id;
        outcome_.pixel_classes.insert(id);
        continue;
      }
      int x, y;
      xy(p, &x, &y);
      bad.Add(x, y, "class id " + std::to_string(id));
    }
    if (Selected("layer.classid-known")) {
      EmitTally("layer.classid-known",
                FileOf("classid"),
                bad,
                "with a class id that is not in the class table");
    }
  }
}

void FrameChecker::CheckBundle() {
  if (!bundle_) return;
  const DeepImage& deep = *bundle_;
  const std::string file = FileOf("bundle");
  const exr::DeepChannel* z = deep.Find("Z");
  const exr::DeepChannel* sx = deep.Find("SX");
  const exr::DeepChannel* sy = deep.Find("SY");
  if (Selected("layer.bundle")) {
    CheckTimer timer(&outcome_.check_seconds, {"layer.bundle"});
    PixelTally empty, bad_z, bad_position;
    for (int y = 0; y < deep.height(); ++y) {
      for (int x = 0; x < deep.width(); ++x) {
        const uint32_t count = deep.SampleCount(x, y);
        if (count == 0) empty.Add(x, y);
        const uint64_t first = deep.FirstSample(x, y);
        for (uint32_t s = 0; s < count; ++s) {
          if (z && z->floats.size() == deep.total_samples()) {
            const float d = z->floats[first + s];
            if (std::isnan(d) || d < 0)
              bad_z.Add(x, y, "sample " + std::to_string(s) + " Z = " + Fmt(d));
          }
          if (sx && sy && sx->floats.size() == deep.total_samples()) {
            const float a = sx->floats[first + s], b = sy->floats[first + s];
            if (!(a >= 0 && a <= 1 && b >= 0 && b <= 1)) {
              bad_position.Add(x, y, "sample " + std::to_string(s));
            }
          }
        }
      }
    }
    EmitTally("layer.bundle", file, empty, "with no sample");
    EmitTally("layer.bundle", file, bad_z, "with a NaN or negative sample depth");
    EmitTally("layer.bundle", file, bad_position, "with a sample position outside [0, 1]");
  }
  if (Selected("cross.bundle-centre")) {
    CheckTimer timer(&outcome_.check_seconds, {"cross.bundle-centre"});
    struct Pair {
      const char* bundle_channel;
      const char* semantic;
    };
    for (const Pair& pair : {Pair{"instanceid", "instanceid"}, Pair{"classid", "classid"}}) {
      const exr::DeepChannel* samples = deep.Find(pair.bundle_channel);
      const std::vector<uint32_t>* ids = Ids(pair.semantic);
      if (!samples || !ids || samples->uints.size() != deep.total_samples() ||
          deep.width() != width_ || deep.height() != height_) {
        continue;
      }
      PixelTally bad;
      for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x) {
          if (deep.SampleCount(x, y) == 0) continue;
          const uint32_t centre = samples->uints[deep.FirstSample(x, y)];
          const uint32_t single = (*ids)[deep.Index(x, y)];
          if (centre != single) {
            bad.Add(x,
                    y,
                    std::string(pair.bundle_channel) + " sample 0 = " + std::to_string(centre) +
                        ", " + pair.semantic + " layer = " + std::to_string(single));
          }
        }
      }
      EmitTally("cross.bundle-centre",
                file,
                bad,
                std::string("whose sample 0 disagrees with the ") + pair.semantic + " layer");
    }
    const std::vector<float>* depth = Channel("depth", 0);
    const LayerInfo* bundle_layer = Layer("bundle");
    const LayerInfo* depth_layer = Layer("depth");
    if (z && depth && z->floats.size() == deep.total_samples() && bundle_layer && depth_layer &&
        bundle_layer->depth_kind == depth_layer->depth_kind && deep.width() == width_ &&
        deep.height() == height_) {
      PixelTally bad;
      for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x) {
          if (deep.SampleCount(x, y) == 0) continue;
          const float centre = z->floats[deep.FirstSample(x, y)];
          const float single = (*depth)[deep.Index(x, y)];
          if (centre == single) continue;
          if (std::abs(centre - single) <= 1e-6 * std::abs(single)) continue;
          bad.Add(x, y, "Z sample 0 = " + Fmt(centre) + ", depth = " + Fmt(single));
        }
      }
      EmitTally(
          "cross.bundle-centre", file, bad, "whose sample 0 depth disagrees with the depth layer");
    }
  }
}

void FrameChecker::CheckObjects() {
  const std::vector<uint32_t>* ids = Ids("instanceid");
  const std::vector<uint32_t>* classes = Ids("classid");
  struct Mask {
    InstanceMask extent;  // the pixel count and the tight box
    PixelTally wrong_class;
    uint32_t wrong_class_id = 0;
  };
  std::unordered_map<uint32_t, Mask> masks;
  std::unordered_map<uint32_t, uint32_t> class_of;
  for (const ObjectTruth& object : frame_.objects) {
    masks[object.instance_id];
    class_of[object.instance_id] = object.class_id;
  }
  if (ids) {
    for (const auto& [id, extent] : MeasureInstanceMasks(*ids, width_, height_)) {
      const auto it = masks.find(id);
      if (it != masks.end()) it->second.extent = extent;
    }
  }
  if (ids && classes) {
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        const size_t p = static_cast<size_t>(y) * width_ + x;
        const auto it = masks.find((*ids)[p]);
        if (it == masks.end()) continue;
        if ((*classes)[p] != class_of[(*ids)[p]]) {
          it->second.wrong_class.Add(x, y, "classid " + std::to_string((*classes)[p]));
        }
      }
    }
  }
  const bool can_project = frame_.camera.cam_from_world_rotation.determinant() > 0;
  const Rigid3d cam_from_world = CamFromWorld(frame_.camera);
  for (size_t k = 0; k < frame_.objects.size(); ++k) {
    const ObjectTruth& object = frame_.objects[k];
    const std::string pointer = "/objects/" + std::to_string(k);
    const ClassInfo* info = header_.FindClass(object.class_id);
    const std::string who = "instance " + std::to_string(object.instance_id) +
                            (object.name.empty() ? "" : " '" + object.name + "'") +
                            (info ? " (" + info->name + ")" : "");
    if (ids) {
      const Mask& m = masks[object.instance_id];
      std::optional<Box2d> extent;
      if (m.extent.pixels > 0) extent = m.extent.box;
      auto box_text = [](const std::optional<Box2d>& b) {
        return b ? "[" + Fmt(b->x0) + ", " + Fmt(b->y0) + ", " + Fmt(b->x1) + ", " + Fmt(b->y1) +
                       "]"
                 : std::string("null");
      };
      const bool equal =
          extent.has_value() == object.bbox.has_value() && (!extent || *extent == *object.bbox);
      if (!equal) {
        Emit("cross.bbox-tight",
             JsonLocation(pointer + "/bbox"),
             "bbox is " + box_text(object.bbox) + " but the instance mask in " +
                 FileOf("instanceid") + " spans " + box_text(extent),
             who);
      }
      if (m.extent.pixels != object.visible_pixels) {
        Emit("cross.visible-pixels",
             JsonLocation(pointer + "/visible_pixels"),
             "visible_pixels is " + std::to_string(object.visible_pixels) + " but the mask has " +
                 std::to_string(m.extent.pixels) + " pixels",
             who);
      }
      if (m.wrong_class.count > 0 && Selected("cross.class-instance")) {
        Emit("cross.class-instance",
             Location::Pixel(FileOf("classid"), frame_.index, m.wrong_class.x, m.wrong_class.y),
             std::to_string(m.wrong_class.count) +
                 " pixel(s) of the instance carry another class than " +
                 std::to_string(object.class_id) + "; first: " + m.wrong_class.first_detail,
             who);
      }
    }
    if (Selected("cross.oriented-box")) {
      CheckOrientedBoxes(
          object, pointer, who, ids ? masks[object.instance_id].extent : InstanceMask{});
    }
    if (object.bbox && can_project && Selected("cross.obb-contains-bbox")) {
      const auto projected = ProjectedBounds(object.obb, frame_.camera.intrinsics, cam_from_world);
      const Box2d clipped = projected ? projected->ClippedTo(width_, height_) : Box2d{};
      if (!projected || !clipped.Contains(*object.bbox, 1.0)) {
        Emit("cross.obb-contains-bbox",
             JsonLocation(pointer + "/bbox"),
             "the OBB projected through the declared camera covers [" + Fmt(clipped.x0) + ", " +
                 Fmt(clipped.y0) + ", " + Fmt(clipped.x1) + ", " + Fmt(clipped.y1) +
                 "], which does not contain the tight bbox [" + Fmt(object.bbox->x0) + ", " +
                 Fmt(object.bbox->y0) + ", " + Fmt(object.bbox->x1) + ", " + Fmt(object.bbox->y1) +
                 "]",
             who);
      }
    }
  }
}

// The oriented boxes of format 1.2 (docs/format.md, "Oriented boxes"); an
// object without them (older collections) has nothing to check.
void FrameChecker::CheckOrientedBoxes(const ObjectTruth& object,
                                      const std::string& pointer,
                                      const std::string& who,
                                      const InstanceMask& extent) {
  for (const auto& [key, box] :
       {std::pair{"bbox_oriented", &object.bbox_oriented},
        std::pair{"bbox_oriented_projected", &object.bbox_oriented_projected}}) {
    if (!*box) continue;
    if (const std::string problem = RectangleProblem(**box); !problem.empty())
      Emit("cross.oriented-box",
           JsonLocation(pointer + "/" + key),
           std::string(key) + " is not a rectangle with clockwise corners: " + problem,
           who);
  }
  const std::vector<uint32_t>* ids = Ids("instanceid");
  if (!ids || !object.bbox_oriented) return;
  const OrientedBox2d& box = *object.bbox_oriented;
  const Location where = JsonLocation(pointer + "/bbox_oriented");
  if (extent.pixels == 0) {
    Emit("cross.oriented-box",
         where,
         "bbox_oriented is given but the instance mask in " + FileOf("instanceid") +
             " has no pixel (it is absent for an object that is not visible)",
         who);
    return;
  }
  // Coverage: a rectangle is convex, so it covers a row's pixels when it
  // covers the outer corners of the row's first and last pixel.
  const int x0 = static_cast<int>(extent.box.x0), x1 = static_cast<int>(extent.box.x1);
  for (int y = static_cast<int>(extent.box.y0); y < static_cast<int>(extent.box.y1); ++y) {
    const uint32_t* row = ids->data() + static_cast<size_t>(y) * width_;
    int first = -1, last = -1;
    for (int x = x0; x < x1; ++x) {
      if (row[x] != object.instance_id) continue;
      if (first < 0) first = x;
      last = x;
    }
    if (first < 0) continue;
    for (const int x : {first, last}) {
      for (const Eigen::Vector2d& corner : {Eigen::Vector2d(x, y),
                                            Eigen::Vector2d(x + 1, y),
                                            Eigen::Vector2d(x, y + 1),
                                            Eigen::Vector2d(x + 1, y + 1)}) {
        if (box.Contains(corner, 1e-6)) continue;
        Emit("cross.oriented-box",
             where,
             "bbox_oriented does not cover pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                 ") of the instance mask in " + FileOf("instanceid") + ": its corner " +
                 PointText(corner) + " lies outside",
             who);
        return;
      }
    }
  }
  // Minimal area: that of the minimum-area rectangle of the mask (a covering
  // box is never smaller, up to rounding).
  const std::optional<OrientedBox2d> minimal =
      MaskOrientedBox(ids->data(), width_, height_, object.instance_id, extent.box);
  if (minimal && std::abs(box.Area() - minimal->Area()) > 1e-6 * minimal->Area()) {
    Emit("cross.oriented-box",
         where,
         "bbox_oriented has area " + Fmt(box.Area()) +
             " px^2 but the minimum-area rectangle of the instance mask in " +
             FileOf("instanceid") + " has " + Fmt(minimal->Area()),
         who);
  }
}

void FrameChecker::CheckWorldPositionVsDepth() {
  if (!Selected("cross.worldpos-depth")) return;
  const std::vector<float>* z = Channel("depth", 0);
  const auto *px = Channel("worldposition", 0), *py = Channel("worldposition", 1),
             *pz = Channel("worldposition", 2);
  const LayerInfo* depth_layer = Layer("depth");
  if (!z || !px || !py || !pz || !depth_layer) return;
  const DepthKind kind = depth_layer->depth_kind.value_or(DepthKind::kPlanar);
  const PinholeCamera& camera = frame_.camera.intrinsics;
  const Eigen::Matrix3d world_from_cam = frame_.camera.cam_from_world_rotation.inverse();
  const Eigen::Vector3d t = frame_.camera.cam_from_world_translation;
  Statistic error;
  PixelTally bad;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const size_t p = static_cast<size_t>(y) * width_ + x;
      const float d = (*z)[p];
      const Eigen::Vector3d point((*px)[p], (*py)[p], (*pz)[p]);
      const bool sky_depth = d == INFINITY;
      const bool sky_point = !point.allFinite();
      if (sky_depth || sky_point) {
        if (sky_depth != sky_point)
          bad.Add(x, y, sky_depth ? "sky depth, finite position" : "finite depth, sky position");
        continue;
      }
      if (!std::isfinite(d)) continue;  // layer.depth-finite
      const Eigen::Vector3d in_cam = UnprojectDepth(camera, {x + 0.5, y + 0.5}, d, kind);
      const Eigen::Vector3d back_projected = world_from_cam * (in_cam - t);
      const double e = (back_projected - point).norm();
      error.max = std::max(error.max, e);
      error.sum_squares += e * e;
      ++error.count;
      if (!(e <= 1e-4 * d + 1e-4)) {
        bad.Add(x, y, "error " + Fmt(e) + " at depth " + Fmt(d));
      }
    }
  }
  outcome_.statistics.push_back({"cross.worldpos-depth.error", error});
  if (bad.count > 0) {
    Emit("cross.worldpos-depth",
         Location::Pixel(FileOf("worldposition"), frame_.index, bad.x, bad.y),
         std::to_string(bad.count) + " pixel(s) whose world position is not the " +
             DepthKindName(kind) + " depth of " + FileOf("depth") +
             " back-projected through the declared camera (max error " + Fmt(error.max) + ", RMS " +
             Fmt(error.rms()) + " world units); first: " + bad.first_detail);
  }
}

void FrameChecker::CheckMotion() {
  const auto *mx = Channel("motion", 0), *my = Channel("motion", 1);
  if (!mx || !my) return;
  // The first frame of a shot has nothing to move from.
  if (input_.shot_start && Selected("cross.motion-invalid")) {
    PixelTally bad;
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x) {
        const size_t p = static_cast<size_t>(y) * width_ + x;
        if (!std::isnan((*mx)[p]) || !std::isnan((*my)[p]))
          bad.Add(x, y, "motion (" + Fmt((*mx)[p]) + ", " + Fmt((*my)[p]) + ")");
      }
    EmitTally("cross.motion-invalid",
              FileOf("motion"),
              bad,
              "with a motion value on the first frame of a shot (expected NaN)");
  }
  if (!input_.previous_camera) return;
  const bool check_pose = Selected("cross.motion-pose");
  const bool check_invalid = Selected("cross.motion-invalid");
  if (!check_pose && !check_invalid) return;
  const auto *px = Channel("worldposition", 0), *py = Channel("worldposition", 1),
             *pz = Channel("worldposition", 2);
  if (!px || !py || !pz) return;
  const CameraTruth& previous = *input_.previous_camera;
  const PinholeCamera& camera = previous.intrinsics;
  // Objects whose box moved since the previous frame (LCAP moves and
  // changes): their points move with the box, from the unit box of now to
  // the box of then.
  std::map<uint32_t, std::pair<OrientedBox, OrientedBox>> moved;
  for (const ObjectTruth& o : input_.frame.objects) {
    const auto before = input_.previous_boxes.find(o.instance_id);
    if (before == input_.previous_boxes.end()) continue;
    const OrientedBox& b = before->second;
    if (b.center != o.obb.center || b.half_extents != o.obb.half_extents ||
        b.world_from_box != o.obb.world_from_box)
      moved[o.instance_id] = {o.obb, b};
  }
  const std::vector<uint32_t>* instances = moved.empty() ? nullptr : Ids("instanceid");
  int64_t checked = 0, unseen = 0;
  PixelTally bad, unmarked;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const size_t p = static_cast<size_t>(y) * width_ + x;
      Eigen::Vector3d point((*px)[p], (*py)[p], (*pz)[p]);
      if (!point.allFinite()) continue;
      const bool marked = std::isnan((*mx)[p]);
      if (instances) {
        const auto m = moved.find((*instances)[p]);
        if (m != moved.end()) {
          const OrientedBox &now = m->second.first, &then = m->second.second;
          const Eigen::Vector3d unit = (now.world_from_box.transpose() * (point - now.center))
                                           .cwiseQuotient(now.half_extents.cwiseMax(1e-12));
          point = then.world_from_box * unit.cwiseProduct(then.half_extents) + then.center;
        }
      }
      const Eigen::Vector3d in_previous =
          previous.cam_from_world_rotation * point + previous.cam_from_world_translation;
      // Where a static point was in the previous image; a point behind that
      // camera or more than a pixel outside its image was not seen there.
      Eigen::Vector2d before(0, 0);
      bool seen = in_previous.z() > 0;
      if (seen) {
        before = camera.ImageFromCam(in_previous);
        seen = before.x() > -1 && before.x() < camera.width + 1 && before.y() > -1 &&
               before.y() < camera.height + 1;
      }
      if (!seen) {
        ++unseen;
        if (!marked)
          unmarked.Add(x,
                       y,
                       "motion (" + Fmt((*mx)[p]) + ", " + Fmt((*my)[p]) +
                           ") for a point the previous camera did not see");
        continue;
      }
      if (marked) continue;  // disoccluded or moved: no static expectation
      const Eigen::Vector2d shift = Eigen::Vector2d(x + 0.5, y + 0.5) - before;
      const double ex = 0.5 + 0.5 * shift.x() / width_, ey = 0.5 + 0.5 * shift.y() / height_;
      ++checked;
      if (std::abs((*mx)[p] - ex) > 2e-3 || std::abs((*my)[p] - ey) > 2e-3) {
        bad.Add(x,
                y,
                "motion (" + Fmt((*mx)[p]) + ", " + Fmt((*my)[p]) + "), pose change says (" +
                    Fmt(ex) + ", " + Fmt(ey) + ")");
      }
    }
  }
  // Moving objects legitimately differ; a large share of disagreeing pixels is
  // a defect.
  if (check_pose && checked > 0 && bad.count > checked / 10) {
    Emit("cross.motion-pose",
         Location::Pixel(FileOf("motion"), frame_.index, bad.x, bad.y),
         std::to_string(bad.count) + " of " + std::to_string(checked) +
             " pixels disagree with the camera motion since the previous "
             "frame; first: " +
             bad.first_detail);
  }
  if (check_invalid && unseen > 0 && unmarked.count > unseen / 10) {
    Emit("cross.motion-invalid",
         Location::Pixel(FileOf("motion"), frame_.index, unmarked.x, unmarked.y),
         std::to_string(unmarked.count) + " of " + std::to_string(unseen) +
             " pixels that the previous frame's camera did not see carry a "
             "motion value instead of NaN; first: " +
             unmarked.first_detail);
  }
}

void FrameChecker::CheckCamera() {
  if (!context_.checks->HasGroup("camera")) return;
  const FlatImage* worldposition = Flat("worldposition");
  const LayerInfo* wp_layer = Layer("worldposition");
  if (!worldposition || !wp_layer || wp_layer->channels.size() < 3) return;
  CameraCheckInput in;
  in.frame = &frame_;
  in.worldposition = worldposition;
  in.worldposition_file = FileOf("worldposition");
  if (const LayerInfo* depth_layer = Layer("depth"); depth_layer && Flat("depth")) {
    in.depth = Flat("depth");
    in.depth_channel = depth_layer->channels[0].name;
    in.depth_file = FileOf("depth");
    in.depth_kind = depth_layer->depth_kind.value_or(DepthKind::kPlanar);
  }
  in.grid = context_.camera_grid;
  const double rms = CheckCameraGeometry(in, *context_.checks, &outcome_.findings);
  if (rms >= 0) {
    Statistic s;
    s.max = rms, s.sum_squares = rms * rms, s.count = 1;
    outcome_.statistics.push_back({"camera.reprojection_rms_px", s});
  }
}

}  // namespace

FrameOutcome CheckFrame(const FrameCheckContext& context, const FrameInput& input) {
  return FrameChecker(context, input).Run();
}

}  // namespace lsds::validate
