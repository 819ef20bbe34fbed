#include "validators/frame_checker.h"

#include <cmath>
#include <optional>

namespace lsds::validate::detail {

namespace {

// Tallies the pixels of a width x height layer for which `problem(p)` names a problem
// (nullopt: the pixel passes); p is the pixel's index, row by row.
template <typename Problem>
void TallyPixels(int width, int height, PixelTally* tally, Problem problem) {
  const size_t n = static_cast<size_t>(width) * height;
  for (size_t p = 0; p < n; ++p) {
    if (std::optional<std::string> detail = problem(p)) {
      tally->Add(static_cast<int>(p % width), static_cast<int>(p / width), *detail);
    }
  }
}

}  // namespace

// The layer value checks, one small method each, in the order their findings are reported.
// Each one checks its own selection and charges its own time (CheckTimer), so that a layer
// that is absent or not selected costs nothing.
void FrameChecker::CheckValues() {
  static constexpr void (FrameChecker::*kValueChecks[])() = {
      &FrameChecker::CheckRgbRange,
      &FrameChecker::CheckDepthFinite,
      &FrameChecker::CheckNormalUnit,
      &FrameChecker::CheckWorldPositionFinite,
      &FrameChecker::CheckShadowRange,
      &FrameChecker::CheckMotionRange,
      &FrameChecker::CheckClassIdKnown,
  };
  for (const auto check : kValueChecks) (this->*check)();
}

void FrameChecker::CheckRgbRange() {
  const LayerInfo* layer = Layer("rgb");
  if (!layer || !Flat("rgb") || !Selected("layer.rgb-range")) return;
  CheckTimer timer(&outcome_.check_seconds, {"layer.rgb-range"});
  PixelTally bad;
  for (size_t k = 0; k < layer->channels.size(); ++k) {
    const std::vector<float>* v = Channel("rgb", k);
    if (v == nullptr) continue;
    TallyPixels(width_, height_, &bad, [&](size_t p) -> std::optional<std::string> {
      const float value = (*v)[p];
      if (std::isfinite(value) && value >= 0) return std::nullopt;
      return layer->channels[k].name + " = " + Fmt(value);
    });
  }
  EmitTally("layer.rgb-range", FileOf("rgb"), bad, "with non-finite or negative colour");
}

void FrameChecker::CheckDepthFinite() {
  const std::vector<float>* z = Channel("depth", 0);
  if (!z || !Selected("layer.depth-finite")) return;
  CheckTimer timer(&outcome_.check_seconds, {"layer.depth-finite"});
  PixelTally bad;
  TallyPixels(width_, height_, &bad, [&](size_t p) -> std::optional<std::string> {
    const float d = (*z)[p];
    if (!(std::isnan(d) || d < 0 || d == -INFINITY)) return std::nullopt;
    return "depth = " + Fmt(d);
  });
  EmitTally("layer.depth-finite",
            FileOf("depth"),
            bad,
            "with NaN or negative depth (only +inf, for sky, is allowed "
            "beside finite >= 0)");
}

void FrameChecker::CheckNormalUnit() {
  if (!Flat("normal") || !Selected("layer.normal-unit")) return;
  CheckTimer timer(&outcome_.check_seconds, {"layer.normal-unit"});
  const auto *nx = Channel("normal", 0), *ny = Channel("normal", 1), *nz = Channel("normal", 2);
  if (!nx || !ny || !nz) return;
  PixelTally bad;
  TallyPixels(width_, height_, &bad, [&](size_t p) -> std::optional<std::string> {
    const double a = (*nx)[p], b = (*ny)[p], c = (*nz)[p];
    const double length = std::sqrt(a * a + b * b + c * c);
    if (length == 0) return std::nullopt;  // sky
    if (std::abs(length - 1) <= 1e-3) return std::nullopt;
    return "|n| = " + Fmt(length);
  });
  EmitTally("layer.normal-unit", FileOf("normal"), bad, "with a normal of length != 1");
}

void FrameChecker::CheckWorldPositionFinite() {
  if (!Flat("worldposition") || !Selected("layer.worldposition-finite")) return;
  CheckTimer timer(&outcome_.check_seconds, {"layer.worldposition-finite"});
  const auto *px = Channel("worldposition", 0), *py = Channel("worldposition", 1),
             *pz = Channel("worldposition", 2);
  if (!px || !py || !pz) return;
  PixelTally bad;
  TallyPixels(width_, height_, &bad, [&](size_t p) -> std::optional<std::string> {
    const float a = (*px)[p], b = (*py)[p], c = (*pz)[p];
    const bool finite = std::isfinite(a) && std::isfinite(b) && std::isfinite(c);
    const bool sky = a == INFINITY && b == INFINITY && c == INFINITY;
    if (finite || sky) return std::nullopt;
    return "(" + Fmt(a) + ", " + Fmt(b) + ", " + Fmt(c) + ")";
  });
  EmitTally("layer.worldposition-finite",
            FileOf("worldposition"),
            bad,
            "with a non-finite world position that is not sky (+inf, +inf, "
            "+inf)");
}

void FrameChecker::CheckShadowRange() {
  const LayerInfo* layer = Layer("shadow");
  if (!layer || !Flat("shadow") || !Selected("layer.shadow-range")) return;
  CheckTimer timer(&outcome_.check_seconds, {"layer.shadow-range"});
  PixelTally bad;
  for (size_t k = 0; k < layer->channels.size(); ++k) {
    const std::vector<float>* v = Channel("shadow", k);
    if (v == nullptr) continue;
    TallyPixels(width_, height_, &bad, [&](size_t p) -> std::optional<std::string> {
      const float value = (*v)[p];
      if (value >= 0 && value <= 1) return std::nullopt;
      return layer->channels[k].name + " = " + Fmt(value);
    });
  }
  EmitTally("layer.shadow-range", FileOf("shadow"), bad, "outside [0, 1]");
}

// Motion may exceed [0, 1] (motion beyond one image size); NaN marks a pixel
// with no valid motion and must be NaN on both channels.
void FrameChecker::CheckMotionRange() {
  if (!Flat("motion") || !Selected("layer.motion-range")) return;
  CheckTimer timer(&outcome_.check_seconds, {"layer.motion-range"});
  const auto *mx = Channel("motion", 0), *my = Channel("motion", 1);
  if (!mx || !my) return;
  PixelTally bad;
  TallyPixels(width_, height_, &bad, [&](size_t p) -> std::optional<std::string> {
    const float a = (*mx)[p], b = (*my)[p];
    const bool valid = std::isfinite(a) && std::isfinite(b);
    const bool invalid = std::isnan(a) && std::isnan(b);
    if (valid || invalid) return std::nullopt;
    return "(" + Fmt(a) + ", " + Fmt(b) + ")";
  });
  EmitTally("layer.motion-range",
            FileOf("motion"),
            bad,
            "whose motion is neither finite nor NaN on both channels");
}

// Also collects the class ids the frame shows (outcome_.pixel_classes), selected or not.
void FrameChecker::CheckClassIdKnown() {
  const std::vector<uint32_t>* ids = Ids("classid");
  if (!ids) return;
  CheckTimer timer(&outcome_.check_seconds, Chosen({"layer.classid-known"}));
  PixelTally bad;
  uint32_t last_known = 0;
  TallyPixels(width_, height_, &bad, [&](size_t p) -> std::optional<std::string> {
    const uint32_t id = (*ids)[p];
    if (id == 0 || id == last_known) return std::nullopt;
    if (header_.FindClass(id) != nullptr) {
      last_known = id;
      outcome_.pixel_classes.insert(id);
      return std::nullopt;
    }
    return "class id " + std::to_string(id);
  });
  if (Selected("layer.classid-known")) {
    EmitTally("layer.classid-known",
              FileOf("classid"),
              bad,
              "with a class id that is not in the class table");
  }
}

// The deep bundle: its samples on their own (layer.bundle), and its centre sample against
// the flat id and depth layers (cross.bundle-centre).
void FrameChecker::CheckBundle() {
  if (!bundle_) return;
  if (Selected("layer.bundle")) {
    CheckTimer timer(&outcome_.check_seconds, {"layer.bundle"});
    CheckBundleSamples();
  }
  if (Selected("cross.bundle-centre")) {
    CheckTimer timer(&outcome_.check_seconds, {"cross.bundle-centre"});
    CheckBundleCentreIds("instanceid", "instanceid");
    CheckBundleCentreIds("classid", "classid");
    CheckBundleCentreDepth();
  }
}

// Every pixel has a sample; sample depths are not NaN or negative; positions lie in the pixel.
void FrameChecker::CheckBundleSamples() {
  const DeepImage& deep = *bundle_;
  const std::string file = FileOf("bundle");
  const exr::DeepChannel* z = deep.Find("Z");
  const exr::DeepChannel* sx = deep.Find("SX");
  const exr::DeepChannel* sy = deep.Find("SY");
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

// Sample 0 (the pixel centre) of the bundle's id channel equals the flat id layer.
void FrameChecker::CheckBundleCentreIds(const char* bundle_channel, const char* semantic) {
  const DeepImage& deep = *bundle_;
  const exr::DeepChannel* samples = deep.Find(bundle_channel);
  const std::vector<uint32_t>* ids = Ids(semantic);
  if (!samples || !ids || samples->uints.size() != deep.total_samples() || deep.width() != width_ ||
      deep.height() != height_) {
    return;
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
                std::string(bundle_channel) + " sample 0 = " + std::to_string(centre) + ", " +
                    semantic + " layer = " + std::to_string(single));
      }
    }
  }
  EmitTally("cross.bundle-centre",
            FileOf("bundle"),
            bad,
            std::string("whose sample 0 disagrees with the ") + semantic + " layer");
}

// Sample 0's depth equals the depth layer's (relative 1e-6), when both are of one kind.
void FrameChecker::CheckBundleCentreDepth() {
  const DeepImage& deep = *bundle_;
  const exr::DeepChannel* z = deep.Find("Z");
  const std::vector<float>* depth = Channel("depth", 0);
  const LayerInfo* bundle_layer = Layer("bundle");
  const LayerInfo* depth_layer = Layer("depth");
  if (!(z && depth && z->floats.size() == deep.total_samples() && bundle_layer && depth_layer &&
        bundle_layer->depth_kind == depth_layer->depth_kind && deep.width() == width_ &&
        deep.height() == height_)) {
    return;
  }
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
  EmitTally("cross.bundle-centre",
            FileOf("bundle"),
            bad,
            "whose sample 0 depth disagrees with the depth layer");
}

}  // namespace lsds::validate::detail
