// Ground detail at the scale of a UAV's pixel (docs/generator.md, "Ground
// detail"): the terrain families' fine structure - grass blades and clumps,
// sand grains, asphalt aggregate, cracks and grain of rock - as octaves of the
// world's gradient noise (generator/scene/perlin.h) in world coordinates, so
// the same ground looks the same from every frame and view. Each octave is
// kept while its wavelength spans at least two of the pixel's footprints on
// the surface and fades out down to one (a mip-map's rule): no aliasing, and
// no work for detail the pixel cannot show.
#pragma once

#include <Eigen/Core>

#include "generator/scene/perlin.h"

namespace lsds::gen {

// A family's detail: octaves of noise from `coarsest_m` down to `finest_m`
// wavelength (each half the last), weighted by `persistence` per octave. A
// Material carries one (materials.h); contrast 0 is no detail.
// Octaves finer than this wavelength (m) are ridged where a detail asks for
// ridges: blades, not clumps.
inline constexpr double kRidgedBelowM = 0.08;

struct GroundDetail {
  float contrast = 0.f;      // the albedo is scaled by 1 +- contrast
  float coarsest_m = 0.5f;   // the first octave's wavelength
  float finest_m = 0.01f;    // no octave finer than this
  float persistence = 0.8f;  // each finer octave's weight relative to the last
  // Octaves finer than 8 cm are ridges (1 - 2 |noise|): thin bright lines
  // between dark gaps, the blades of grass seen from above.
  bool ridged = false;
  // How much brighter the bright end is in each channel (the dry, yellowish
  // tips of grass: red and green more than blue); 1 = grey.
  Eigen::Vector3f tint = Eigen::Vector3f::Ones();
  float bump = 0.f;  // the shading normal tilts by up to about this (radians)
};

// The detail's albedo factor at `point_in_world` for a pixel of footprint
// `footprint_m` on the surface (0: every octave), and its tilt of the shading
// normal (two tangent components, radians), in `tilt` when not null. On a
// `height_field` (the terrain: one surface point per x, y) the octaves are the
// 2D noise of x and y, at half the cost of the 3D noise other surfaces take.
Eigen::Vector3f DetailFactor(const GroundDetail& detail,
                             const Perlin& noise,
                             const Eigen::Vector3f& point_in_world,
                             float footprint_m,
                             Eigen::Vector2f* tilt = nullptr,
                             bool height_field = false);

// The finest wavelength (m) the detail shows at `footprint_m`: its own
// finest, or the footprint where that is coarser. Infinite for no detail.
double DetailFinestWavelength(const GroundDetail& detail, float footprint_m);

// Two unit vectors that make a right-handed frame with the unit `normal`,
// from whichever world axis is least parallel to it.
void TangentFrame(const Eigen::Vector3d& normal, Eigen::Vector3d* t1, Eigen::Vector3d* t2);

// `normal` (unit, world) tilted by `tilt` in its tangent plane.
Eigen::Vector3d TiltedNormal(const Eigen::Vector3d& normal, const Eigen::Vector2f& tilt);

}  // namespace lsds::gen
