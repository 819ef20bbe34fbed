#include "generator/render/shading.h"

#include <algorithm>
#include <cmath>

namespace lsds::gen {

Eigen::Vector3f Shade(const Material& material,
                      const Eigen::Vector3f& albedo,
                      const Eigen::Vector3d& n,
                      const Eigen::Vector3d& ray_direction,
                      const Sky& sky,
                      const Eigen::Vector3f& irradiance,
                      float sun_visible) {
  const float metallic = material.metallic;
  Eigen::Vector3f radiance = (1 - metallic) * albedo.cwiseProduct(irradiance);
  if (material.specular <= 0) return radiance;
  const Eigen::Vector3d to_camera = -ray_direction.normalized();
  // Reflectance at normal incidence: 4 % for dielectrics, the albedo for metals.
  const Eigen::Vector3f f0 = (1 - metallic) * Eigen::Vector3f::Constant(0.04f) + metallic * albedo;
  const double n_v = std::max(1e-4, n.dot(to_camera));
  auto schlick = [&f0](double cos_theta) {
    const float m = static_cast<float>(std::pow(1 - std::clamp(cos_theta, 0.0, 1.0), 5));
    return Eigen::Vector3f(f0 + (Eigen::Vector3f::Ones() - f0) * m);
  };
  // The sky seen in the mirror direction, blurred towards the ambient level as
  // the surface gets rough.
  const Eigen::Vector3d mirror = 2 * n.dot(to_camera) * n - to_camera;
  const float rough = material.roughness;
  const Eigen::Vector3f environment =
      (1 - rough) * sky.Radiance(mirror.normalized()) + rough * sky.ambient();
  Eigen::Vector3f specular = schlick(n_v).cwiseProduct(environment) * (1 - 0.5f * rough);
  // The sun: GGX normal distribution, Smith-Schlick visibility.
  const Eigen::Vector3d& l = sky.to_sun();
  const double n_l = n.dot(l);
  if (n_l > 0 && sun_visible > 0) {
    const Eigen::Vector3d h = (l + to_camera).normalized();
    const double n_h = std::max(0.0, n.dot(h));
    const double alpha = std::max(1e-3, static_cast<double>(rough * rough));
    const double a2 = alpha * alpha;
    const double d = a2 / (M_PI * std::pow(n_h * n_h * (a2 - 1) + 1, 2));
    const double k = alpha / 2;
    const double g = (n_l / (n_l * (1 - k) + k)) * (n_v / (n_v * (1 - k) + k));
    const double brdf_cos = d * g / (4 * n_v);  // times n.l / (4 n.l n.v)
    specular += schlick(h.dot(to_camera)).cwiseProduct(sky.sun_irradiance()) *
                static_cast<float>(std::min(brdf_cos, 50.0) * sun_visible);
  }
  return radiance + material.specular * specular;
}

}  // namespace lsds::gen
