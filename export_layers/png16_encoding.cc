#include "export_layers/png16_encoding.h"

#include <cmath>

namespace lsds::layer_export {

namespace {

// Signed unit values: stored 32768 is exactly 0 (or `centre`), 1..65535 covers
// centre - 1 .. centre + 1 in steps of 1/32767; 0 is kept for "no value".
Png16Encoding Centred(double centre, std::string invalid_meaning) {
  Png16Encoding e;
  e.scale = 1.0 / 32767.0;
  e.offset = centre - 32768.0 / 32767.0;
  e.invalid_stored = 0;
  e.invalid_meaning = std::move(invalid_meaning);
  return e;
}

}  // namespace

std::optional<Png16Encoding> Png16EncodingOf(const std::string& semantic, double depth_step) {
  Png16Encoding e;
  if (semantic == "classid" || semantic == "instanceid") {
    e.integer = true;
    return e;
  }
  if (semantic == "depth") {
    // The depth-PNG convention of RGB-D datasets (TUM, Kinect): 0 = no depth.
    e.scale = depth_step;
    e.invalid_stored = 0;
    e.invalid_meaning = "no surface: +inf (sky) in the EXR";
    e.beyond_range_is_error = true;
    return e;
  }
  if (semantic == "normal")
    return Centred(0.0, "non-finite in the EXR (never in lsds' own layers)");
  if (semantic == "motion") return Centred(0.5, "no valid motion: NaN in the EXR");
  if (semantic == "shadow") {
    e.scale = 1.0 / 65535.0;  // [0, 1] onto the full range
    return e;
  }
  return std::nullopt;
}

double Png16StepFor(double value) {
  const double needed = value / 65535.0;
  double decade = std::pow(10.0, std::floor(std::log10(needed)));
  for (;; decade *= 10)
    for (const double mantissa : {1.0, 2.0, 5.0})
      if (mantissa * decade * 65535.0 >= value) return mantissa * decade;
}

uint16_t EncodeFloat(const Png16Encoding& encoding, float value, EncodeOutcome* outcome) {
  if (!std::isfinite(value)) {
    if (encoding.invalid_stored) {
      *outcome = EncodeOutcome::kInvalid;
      return *encoding.invalid_stored;
    }
    *outcome = EncodeOutcome::kClamped;
    return 0;
  }
  const double stored =
      std::nearbyint((static_cast<double>(value) - encoding.offset) / encoding.scale);
  const double lowest = encoding.lowest_valid();
  if (stored < lowest || stored > 65535.0) {
    *outcome = EncodeOutcome::kClamped;
    return static_cast<uint16_t>(stored < lowest ? lowest : 65535.0);
  }
  *outcome = EncodeOutcome::kValue;
  return static_cast<uint16_t>(stored);
}

}  // namespace lsds::layer_export
