// How each layer semantic is quantised into a 16-bit PNG: one linear map per
// layer, written into the export's layers.json so that reading back is exact
// (ids) or within half a step (everything else). docs/export-layers.md.
//
//   value = stored * scale + offset          for stored != invalid_stored
//   stored == invalid_stored                 no value (sky depth, NaN motion)
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace lsds::layer_export {

struct Png16Encoding {
  double scale = 1;
  double offset = 0;
  // The stored value of pixels without a value (non-finite in the EXR); unset
  // when the layer has none (ids: 0 is a real id, "background").
  std::optional<uint16_t> invalid_stored;
  std::string invalid_meaning;  // what such a pixel is in the EXR
  bool integer = false;         // ids: copied, never rounded; > 65535 is an error
  // A finite value beyond the range is an error rather than clamped (depth: a clamped depth is a
  // wrong distance, where a clamped motion or normal only saturates).
  bool beyond_range_is_error = false;

  uint16_t lowest_valid() const { return invalid_stored ? 1 : 0; }
};

// The encoding of a layer semantic, or nullopt when 16 bits cannot hold it
// (worldposition: unbounded signed coordinates; rgb: HDR radiance; derived
// layers: unknown range). `depth_step` is the depth quantum in the collection's
// length unit (0.001: millimetres for a metre collection).
std::optional<Png16Encoding> Png16EncodingOf(const std::string& semantic, double depth_step);

enum class EncodeOutcome { kValue, kInvalid, kClamped };

// Quantises a float value. Non-finite values become invalid_stored (kInvalid);
// values outside the range are clamped to it (kClamped). A non-finite value in a
// layer without an invalid code is clamped to 0 and reported as kClamped.
uint16_t EncodeFloat(const Png16Encoding& encoding, float value, EncodeOutcome* outcome);

// The smallest step of 1, 2 or 5 times a power of ten whose 65535 steps reach `value`: what
// `--depth-step` needs for a depth of `value`.
double Png16StepFor(double value);

inline double DecodePng16(const Png16Encoding& encoding, uint16_t stored) {
  return stored * encoding.scale + encoding.offset;
}

}  // namespace lsds::layer_export
