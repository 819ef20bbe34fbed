// The surface response: Lambertian diffuse plus, for glossy and metallic
// materials (Material::specular > 0), a GGX microfacet lobe for the sun and a
// Fresnel-weighted reflection of the sky, so that metals look like metals
// (tinted, bright reflections, no diffuse) and paint and plastic show
// highlights. Materials with specular 0 keep exactly albedo * irradiance.
#pragma once

#include <Eigen/Core>

#include "generator/render/sky.h"
#include "generator/scene/materials.h"

namespace lsds::gen {

// Radiance leaving a surface towards the camera. `n` the shading normal, a
// unit world vector; `ray_direction` the camera ray's world direction, of any
// length (normalized only for a specular material, the rest do not need it);
// `irradiance` = ambient + sun * cos * visible (the diffuse lighting the
// shadow layer is defined on); `sun_visible` in [0, 1].
Eigen::Vector3f Shade(const Material& material,
                      const Eigen::Vector3f& albedo,
                      const Eigen::Vector3d& n,
                      const Eigen::Vector3d& ray_direction,
                      const Sky& sky,
                      const Eigen::Vector3f& irradiance,
                      float sun_visible);

}  // namespace lsds::gen
