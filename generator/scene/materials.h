// Procedural materials: a named albedo with a spatial pattern, evaluated at a
// world point (docs/generator.md, "Materials"), and a specular/metallic lobe
// (generator/render/shading.h). The names are what LSCENE's `material`
// properties and the terrain refer to. Albedos are linear and measured-like:
// dry sand 0.3-0.4, grass 0.1-0.2, asphalt 0.05-0.1, fresh snow 0.8.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "generator/scene/ground_detail.h"
#include "generator/scene/perlin.h"

namespace lsds::gen {

// The spatial pattern of a material family, on top of the two-scale mottling
// every material has.
enum class Pattern {
  kMottled,  // fractal noise only (grass, soil, paint, ...)
  kSpeckle,  // small grains of `secondary` (asphalt aggregate, sand grains, concrete)
  kStrata,   // bands along the height, warped by noise (rock)
  kBrushed,  // streaks along the world x axis (brushed metal)
};

struct Material {
  std::string name;
  Eigen::Vector3f base;       // linear albedo
  Eigen::Vector3f secondary;  // mixed in by the pattern
  float frequency = 1.f;      // pattern cycles per metre
  float contrast = 0.5f;      // [0, 1] share of `secondary` at the pattern's peaks
  // Specular lobe (generator/render/shading.h): 0 = pure Lambertian (the
  // terrain families, so that their radiance stays albedo * irradiance).
  float specular = 0.f;   // [0, 1] weight of the specular term
  float metallic = 0.f;   // [0, 1]: 1 tints the reflection by the albedo and has no diffuse
  float roughness = 1.f;  // GGX roughness (alpha = roughness^2)
  Pattern pattern = Pattern::kMottled;
  // Large patches (at frequency / 8): the albedo is scaled by 1 +- patches
  // (dry and damp ground, wear, dirt), so no two stretches look the same.
  float patches = 0.f;
  // Fine detail at the scale of a pixel (ground_detail.h): the terrain
  // families' blades, grains and aggregate, and their tilt of the normal.
  GroundDetail detail = {};
};

// The built-in material table (grassy, sandy, rocky, snowy, soil, asphalt,
// concrete, metal, ...).
const std::vector<Material>& MaterialTable();
const std::vector<std::string>& MaterialNames();
// Throws lsds::Error (with a "did you mean") for unknown names; `where` names
// the plan entity.
const Material& FindMaterial(const std::string& name, const std::string& where);

// Albedo of `material` at a world point; `noise` is the material noise field of
// the world. `footprint_m` is the pixel's footprint on the surface, which
// decides the finest detail shown (0: all of it); `tilt` (optional) receives
// the detail's tilt of the shading normal (TiltedNormal); `height_field`: the
// point is on the terrain (DetailFactor).
Eigen::Vector3f Albedo(const Material& material,
                       const Perlin& noise,
                       const Eigen::Vector3f& point_in_world,
                       float footprint_m = 0,
                       Eigen::Vector2f* tilt = nullptr,
                       bool height_field = false);

// How far (m) the procedural albedo may be taken as constant: 1/32 of the
// finest wavelength of its pattern and patches, over which it changes by well
// under an 8-bit step (tests/generator/scene_test.cc). Infinite for a plain
// albedo; 0 for speckle, whose thresholded grains have hard edges. The renderer
// reuses a pixel's albedo within this distance (docs/generator.md, "Smooth
// fields once per pixel"). The detail counts down to the finest wavelength it
// shows at `footprint_m` (0: all of it).
double AlbedoReuseDistance(const Material& material, float footprint_m = 0);

}  // namespace lsds::gen
