// Sky and sun: a clear sky whose luminance follows the Perez / Preetham model
// (A. J. Preetham, P. Shirley, B. Smits, "A practical analytic model for
// daylight", SIGGRAPH 1999) from the sun's position and the air's turbidity,
// coloured from the zenith's colour to a whiter horizon, with procedural
// clouds (type and density); a sun as a directional light; the skylight as
// an ambient term; and haze: distance fog plus the air's own extinction,
// towards the sky's horizon in the ray's azimuth, so distant ground melts
// into the sky with no seam.
#pragma once

#include <Eigen/Core>

#include "generator/plan/plan.h"
#include "generator/scene/perlin.h"

namespace lsds::gen {

// The cloud deck's height above z = 0 (m), and the sun's disc in the sky's
// radiance: directions within this cosine of the sun (about 1.8 degrees).
// The scene export reproduces both (generator/scene_export/sky_export.cc).
inline constexpr double kCloudDeckM = 1000;
inline constexpr double kSunDiscCos = 0.9995;

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
  // The light (irradiance / pi) that surfaces around reflect, albedo
  // kBounceAlbedo, for the sky-light rays (generator/render/integrator.cc):
  // open ground, below the horizon, lit by the sky and by the sun, whose
  // share of indirect light the skylight intensity scales as it scales the
  // sky's; and a surface that blocks a ray, lit by the sky alone (mostly the
  // shaded side of what casts the shadow).
  const Eigen::Vector3f& ground_bounce() const { return ground_bounce_; }
  const Eigen::Vector3f& blocker_bounce() const { return blocker_bounce_; }
  const Eigen::Vector3f& horizon() const { return horizon_; }
  const Eigen::Vector3f& zenith() const { return zenith_; }
  double fog_density() const { return fog_density_; }
  // The Preetham turbidity of the air: 2.5 (clear) plus 1000 x the fog
  // density, at most 10.
  double turbidity() const { return turbidity_; }
  // The share of light from a surface `distance_m` away that reaches the
  // camera through the haze: the fog (fog_density() per metre) and, past
  // kClearAirM, the air's own extinction (Koschmieder: 3.912 / visibility, a
  // visibility of 80 km / (turbidity - 1)), which melts the farthest ground
  // into the sky's horizon and leaves a UAV's working range crisp.
  double HazeTransmittance(double distance_m) const;
  // The steepest the haze's exponent gets per metre: fog and air together.
  double extinction() const { return fog_density_ + air_extinction_; }
  // The colour distant things fade to along a direction: the clear sky at
  // the horizon in its azimuth (no sun disc, no clouds).
  Eigen::Vector3f Haze(const Eigen::Vector3d& direction_in_world) const;
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
  // The clear sky (no disc, no clouds) along a unit direction at or above
  // the horizon.
  Eigen::Vector3f ClearSky(const Eigen::Vector3d& direction) const;
  // The Perez function of luminance at zenith angle cos `cos_theta` and angle
  // `gamma` (radians) from the sun.
  double Perez(double cos_theta, double gamma) const;
  void InitCloudReuse();
  void InitClearSky(const PlannedSky& sky);
  // The deck's noise at (x, y) kilometres, and the noise above which it has
  // clouds.
  double CloudNoiseAt(double x_km, double y_km) const;
  double CloudThreshold() const;
  // Cover of the deck at (x, y) kilometres, [0, 1].
  double CloudCoverAt(double x_km, double y_km) const;

  Eigen::Vector3f zenith_, horizon_, sun_irradiance_, ambient_, ground_bounce_, blocker_bounce_;
  Eigen::Vector3d to_sun_;
  double fog_density_ = 0;
  double turbidity_ = 2.5, air_extinction_ = 0;
  double perez_[5] = {0, 0, 0, 0, 0};  // A..E
  double zenith_perez_ = 1;            // Perez at the zenith
  float zenith_luminance_ = 0;
  Eigen::Vector3f zenith_colour_, horizon_colour_;  // of luminance 1
  double cloud_density_ = 0;
  double cloud_frequency_ = 1, cloud_stretch_ = 1, cloud_softness_ = 0.2;
  double cloud_reuse_distance_ = 0;
  double cloud_noise_slope_ = 0;  // per metre on the ground
  Perlin noise_;
  Perlin texture_noise_;
};

const std::vector<std::string>& CloudTypes();

// How far (m) the air itself is taken as clear (Sky::HazeTransmittance).
constexpr double kClearAirM = 2000;

// The albedo of the average surface that reflects light onto another (ground,
// walls, foliage): Sky::ground_bounce(), Sky::blocker_bounce().
constexpr float kBounceAlbedo = 0.2f;

}  // namespace lsds::gen
