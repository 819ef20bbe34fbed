// Sky and sun: a zenith-to-horizon gradient with procedural clouds (type and
// density), a sun as a directional light, the skylight as an ambient term and
// distance fog towards the horizon colour.
#pragma once

#include <Eigen/Core>

#include "generator/plan/plan.h"
#include "generator/scene/perlin.h"

namespace lsds::gen {

class Sky {
 public:
  // The sky of the plan's own environment, or of a frame's (LCAP changes).
  explicit Sky(const Plan& plan);
  Sky(const Plan& plan, const PlannedEnvironment& environment);

  // Radiance seen along a world direction that hits nothing.
  Eigen::Vector3f Radiance(const Eigen::Vector3d& direction_in_world) const;
  // Unit vector towards the sun: azimuth from north (+y) clockwise towards east
  // (+x).
  const Eigen::Vector3d& to_sun() const { return to_sun_; }
  const Eigen::Vector3f& sun_irradiance() const { return sun_irradiance_; }
  const Eigen::Vector3f& ambient() const { return ambient_; }
  const Eigen::Vector3f& horizon() const { return horizon_; }
  const Eigen::Vector3f& zenith() const { return zenith_; }
  double fog_density() const { return fog_density_; }
  // The share of direct sunlight that reaches world point `p` through the
  // cloud deck (1 km above z = 0): 1 under a clear sky, down to
  // 1 - kCloudOpacity under a full cloud. The same cloud field the sky shows
  // (CloudCoverAt), so cloud shadows on the ground match the clouds above.
  // `reuse_distance` (optional) receives how far (m) around `p` the value may
  // be taken as constant (PixelField): CloudReuseDistance() where the cover
  // ramps; where the deck is clear or full, as far as it stays so, within which
  // the value is exact. Infinite without clouds. `exact_distance` (optional)
  // receives how far the value is exactly the same: that last distance, 0
  // where the cover ramps.
  double CloudTransmittance(const Eigen::Vector3d& p,
                            double* reuse_distance = nullptr,
                            double* exact_distance = nullptr) const;
  // The reuse distance where the cover ramps: 1/64 of the deck's finest
  // wavelength as seen along the sun's rays, scaled by the ramp's softness.
  double CloudReuseDistance() const { return cloud_reuse_distance_; }
  // The reuse distance at `p` when `p` lies `remaining` metres inside a
  // stretch where the transmittance is exactly constant: that far, and at
  // least the ramp's, as CloudTransmittance gives it; not past the deck.
  double CloudReuseDistanceInside(const Eigen::Vector3d& p, double remaining) const;
  // The noise field of procedural material textures.
  const Perlin& texture_noise() const { return texture_noise_; }

 private:
  double CloudCover(const Eigen::Vector3d& direction) const;
  void InitCloudReuse();
  // The deck's noise at (x, y) kilometres, and the noise above which it has
  // clouds.
  double CloudNoiseAt(double x_km, double y_km) const;
  double CloudThreshold() const;
  // Cover of the deck at (x, y) kilometres, [0, 1].
  double CloudCoverAt(double x_km, double y_km) const;

  Eigen::Vector3f zenith_, horizon_, sun_irradiance_, ambient_;
  Eigen::Vector3d to_sun_;
  double fog_density_ = 0;
  double cloud_density_ = 0;
  double cloud_frequency_ = 1, cloud_stretch_ = 1, cloud_softness_ = 0.2;
  double cloud_reuse_distance_ = 0;
  double cloud_noise_slope_ = 0;  // per metre on the ground
  Perlin noise_;
  Perlin texture_noise_;
};

const std::vector<std::string>& CloudTypes();

}  // namespace lsds::gen
