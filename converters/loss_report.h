// What a conversion dropped, clipped, merged or filled, counted per reason and
// per class.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace lsds::convert {

// Reasons (docs/convert.md, "Loss report"). Dropped objects are counted under
// their collection class name, kept ones under their output class name.
namespace loss {
inline constexpr const char* kNotVisible = "dropped: not visible (no box, 0 visible pixels)";
inline constexpr const char* kClassNotSelected = "dropped: class not selected (--classes)";
inline constexpr const char* kMinVisibility = "dropped: visibility below --min-visibility";
inline constexpr const char* kMinTransmittance =
    "dropped: atmospheric transmittance below --min-transmittance";
inline constexpr const char* kMinPixels = "dropped: visible pixels below --min-pixels";
inline constexpr const char* kTruncated =
    "dropped: truncated by the image border (--drop-truncated)";
inline constexpr const char* kNoMask = "dropped: no pixel of the instance in the instanceid layer";
inline constexpr const char* kKept = "kept";
inline constexpr const char* kClippedAtBorder =
    "kept, truncated: box is the visible part inside the image";
inline constexpr const char* kBoxClipped = "box clipped to the image";
inline constexpr const char* kPiecesMerged =
    "polygon: extra pieces bridged into one polygon (yolo-seg)";
inline constexpr const char* kPiecesSplit = "polygon: instance written as several polygons (coco)";
inline constexpr const char* kHolesFilled = "polygon: holes filled";
// Pixel sums behind the polygon IoU (mask pixels / filled polygon pixels) that
// ToText and ToJson report per class.
inline constexpr const char* kPolygonMaskPixels = "polygon: mask pixels written as polygons";
inline constexpr const char* kPolygonHolePixels = "polygon: hole pixels added by filling";
// yolo-seg: what Ultralytics' polygon2mask rasterizes differently from the
// instance mask (filled holes, bridges between pieces).
inline constexpr const char* kPolygon2maskObjects =
    "polygon: Ultralytics' polygon2mask differs from the mask (yolo-seg)";
inline constexpr const char* kPolygon2maskPixels =
    "polygon: pixels where Ultralytics' polygon2mask differs from the mask (yolo-seg)";
// What the oriented-box formats lose (docs/convert.md, "dota", "yolo-obb").
inline constexpr const char* kDotaUnderMinSize =
    "dota: dropped, oriented box side under --dota-min-size px (MMRotate drops it)";
inline constexpr const char* kDotaDifficult = "dota: written with difficult 1";
// Counted under the class name kImages.
inline constexpr const char* kDotaEmptyImages =
    "dota: images without objects (MMRotate skips them when training)";
inline constexpr const char* kObbClipped =
    "yolo-obb: oriented box clipped to the image (minimum-area rectangle of the clipped polygon)";
inline constexpr const char* kObbDuplicate =
    "yolo-obb: rows Ultralytics removes as duplicates (same class and corner bounds)";
inline constexpr const char* kImages = "images";
inline constexpr const char* kMaskBoxMismatch = "mask extends beyond the truth box (box kept)";
}  // namespace loss

class LossReport {
 public:
  void Add(const std::string& reason, const std::string& class_name, int64_t count = 1);
  void CountFrame(const std::string& split, int64_t count = 1) { frames_[split] += count; }
  void Merge(const LossReport& other);

  int64_t Count(const std::string& reason, const std::string& class_name) const;
  int64_t Total(const std::string& reason) const;
  const std::map<std::string, std::map<std::string, int64_t>>& counts() const { return counts_; }

  // Per class, mask pixels / pixels of the filled polygons (1 when no hole
  // was filled); empty when nothing was written as polygons.
  std::map<std::string, double> PolygonIou() const;

  std::string ToText() const;
  nlohmann::json ToJson() const;

 private:
  std::map<std::string, std::map<std::string, int64_t>> counts_;  // reason -> class -> count
  std::map<std::string, int64_t> frames_;                         // split -> frames
};

}  // namespace lsds::convert
