// The per-frame checker behind CheckFrame (frame_checks.h), shared by the files that hold its
// checks; not for use outside validators/.
#pragma once

#include <algorithm>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "libs/collection/model.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/exr_info.h"
#include "libs/exr/flat_image.h"
#include "libs/geometry/instance_mask.h"
#include "libs/util/strings.h"
#include "validators/frame_checks.h"

namespace lsds::validate::detail {

namespace fs = std::filesystem;
using exr::DeepImage;
using exr::FlatImage;

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

inline std::string Fmt(double v) { return FormatNumber(v); }

// One object's mask in the instance id layer, and its pixels of another class.
struct ObjectMask {
  InstanceMask extent;  // the pixel count and the tight box
  PixelTally wrong_class;
  uint32_t wrong_class_id = 0;
};

// One frame's checks: every EXR of the frame is opened and decoded once (LoadLayers), then
// each check reads the decoded images. The checks are methods grouped by kind in
// frame_checks.cc (decoding, headers), frame_value_checks.cc (one layer's values) and
// frame_cross_checks.cc (layers against each other, the truth and the camera).
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
  // Layer value checks (frame_value_checks.cc): one method per check, run from a table.
  void CheckValues();
  void CheckRgbRange();
  void CheckDepthFinite();
  void CheckNormalUnit();
  void CheckWorldPositionFinite();
  void CheckShadowRange();
  void CheckMotionRange();
  void CheckClassIdKnown();
  void CheckBundle();
  void CheckBundleSamples();
  void CheckBundleCentreIds(const char* bundle_channel, const char* semantic);
  void CheckBundleCentreDepth();
  // Cross-layer and camera checks (frame_cross_checks.cc).
  void CheckObjects();
  std::unordered_map<uint32_t, ObjectMask> MeasureObjectMasks(
      const std::vector<uint32_t>* ids, const std::vector<uint32_t>* classes) const;
  void CheckObjectMask(const ObjectTruth& object,
                       const std::string& pointer,
                       const std::string& who,
                       const ObjectMask& mask);
  void CheckObbContainsBbox(const ObjectTruth& object,
                            const std::string& pointer,
                            const std::string& who,
                            const Rigid3d& cam_from_world);
  void CheckOrientedBoxes(const ObjectTruth& object,
                          const std::string& pointer,
                          const std::string& who,
                          const InstanceMask& extent);
  void CheckWorldPositionVsDepth();
  void CheckMotion();
  void CheckShotStartMotion(const std::vector<float>& mx, const std::vector<float>& my);
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

}  // namespace lsds::validate::detail
