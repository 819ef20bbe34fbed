#include "generator/scene/ground_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace lsds::gen {
namespace {

// An octave is whole while its wavelength spans kWholeFootprints pixel
// footprints and gone at kGoneFootprints: the 4 samples of a pixel then
// still resolve it, and finer noise would only alias.
constexpr float kWholeFootprints = 1.0f;
constexpr float kGoneFootprints = 0.5f;

// How much of an octave of wavelength `wavelength` a pixel of `footprint` shows.
float OctaveWeight(float wavelength, float footprint) {
  if (footprint <= 0) return 1.f;
  return std::clamp(
      (wavelength / footprint - kGoneFootprints) / (kWholeFootprints - kGoneFootprints), 0.f, 1.f);
}

// The lean an octave of wavelength `wavelength` gives the normal at `p`, in [-0.5, 0.5]^2.
Eigen::Vector2f DetailTilt(const Perlin& noise,
                           const Eigen::Vector3f& p,
                           float wavelength,
                           bool height_field) {
  const double f = 1.0 / wavelength;
  return {static_cast<float>(height_field ? noise.Noise(p.x() * f + 53.1, p.y() * f)
                                          : noise.Noise(p.x() * f + 53.1, p.y() * f, p.z() * f)),
          static_cast<float>(height_field ? noise.Noise(p.x() * f, p.y() * f + 71.9)
                                          : noise.Noise(p.x() * f, p.y() * f + 71.9, p.z() * f))};
}

}  // namespace

Eigen::Vector3f DetailFactor(const GroundDetail& detail,
                             const Perlin& noise,
                             const Eigen::Vector3f& p,
                             float footprint_m,
                             Eigen::Vector2f* tilt,
                             bool height_field) {
  if (tilt != nullptr) tilt->setZero();
  if (detail.contrast <= 0) return Eigen::Vector3f::Ones();
  double sum = 0, norm = 0, weight = 1;
  float finest_shown = 0, finest_weight = 0, coarser_shown = 0;
  int octave = 0;
  for (float wavelength = detail.coarsest_m; wavelength >= detail.finest_m * 0.999f;
       wavelength *= 0.5f, weight *= detail.persistence, ++octave) {
    norm += weight;
    const float shown = OctaveWeight(wavelength, footprint_m);
    if (shown <= 0) continue;
    const double f = 1.0 / wavelength;
    // Each octave its own offset into the field, so octaves do not line up.
    const double offset = 37.71 * (octave + 1);
    double n = height_field
                   ? noise.Noise(p.x() * f + offset, p.y() * f - offset)
                   : noise.Noise(p.x() * f + offset, p.y() * f - offset, p.z() * f + 0.5 * offset);
    if (detail.ridged && wavelength < static_cast<float>(kRidgedBelowM)) n = 0.4 - 2 * std::abs(n);
    sum += weight * shown * n;
    coarser_shown = finest_shown;
    finest_shown = wavelength;
    finest_weight = shown;
  }
  // Gradient noise stays mostly within +-0.5: twice the normalized sum is
  // about [-1, 1].
  const float d = std::clamp(static_cast<float>(2 * sum / norm), -1.f, 1.f);
  Eigen::Vector3f factor = Eigen::Vector3f::Ones();
  for (int c = 0; c < 3; ++c) factor[c] += detail.contrast * d * (d > 0 ? detail.tint[c] : 1.f);
  if (tilt != nullptr && detail.bump > 0 && finest_weight > 0) {
    // The finest octave shown tilts the normal: blades and grains lean each
    // their own way. While it fades out with distance the next coarser octave
    // fades in, so the tilt never drops to nothing at a footprint (which drew a
    // ring of smooth ground round the nadir point).
    *tilt = detail.bump * finest_weight * DetailTilt(noise, p, finest_shown, height_field);
    if (finest_weight < 1 && coarser_shown > 0)
      *tilt +=
          detail.bump * (1 - finest_weight) * DetailTilt(noise, p, coarser_shown, height_field);
  }
  return factor.cwiseMax(0.f);
}

double DetailFinestWavelength(const GroundDetail& detail, float footprint_m) {
  if (detail.contrast <= 0) return std::numeric_limits<double>::infinity();
  return std::max(detail.finest_m, kGoneFootprints * footprint_m);
}

void TangentFrame(const Eigen::Vector3d& n, Eigen::Vector3d* t1, Eigen::Vector3d* t2) {
  const Eigen::Vector3d axis =
      std::abs(n.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  *t1 = n.cross(axis).normalized();
  *t2 = n.cross(*t1);
}

Eigen::Vector3d TiltedNormal(const Eigen::Vector3d& n, const Eigen::Vector2f& tilt) {
  if (tilt.isZero()) return n;
  Eigen::Vector3d t1, t2;
  TangentFrame(n, &t1, &t2);
  return (n + tilt.x() * t1 + tilt.y() * t2).normalized();
}

}  // namespace lsds::gen
