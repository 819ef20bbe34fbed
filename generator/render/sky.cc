#include "generator/render/sky.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::gen {
namespace {

constexpr double kCloudOpacity = 0.8;  // direct sunlight a full cloud stops

}  // namespace

const std::vector<std::string>& CloudTypes() {
  static const std::vector<std::string> types = {
      "none", "cumulus", "nimbostratus", "cirrus", "stratus"};
  return types;
}

Sky::Sky(const Plan& plan) : Sky(plan, EnvironmentOf(plan)) {}

Sky::Sky(const Plan& plan, const PlannedEnvironment& environment)
    : noise_(HashCombine(plan.seed, 0xc10d)), texture_noise_(HashCombine(plan.seed, 0x7e47)) {
  const PlannedSky& sky = environment.sky;
  // Photometric radiance: RGB whose relative luminance is cd/m^2
  // (docs/generator.md, "Physical light and camera"). The colour gives the
  // zenith's chromaticity, `luminance_cd_m2` its luminance.
  const double color_luminance = RelativeLuminance(sky.color);
  const float sky_scale =
      color_luminance > 0 ? static_cast<float>(sky.luminance_cd_m2 / color_luminance) : 0.f;
  zenith_ = sky.color.cast<float>() * sky_scale;
  horizon_ = (0.5f * sky.color.cast<float>() +
              Eigen::Vector3f::Constant(static_cast<float>(kSkyHorizonWhite))) *
             sky_scale;
  const double el = environment.sun.elevation_deg * M_PI / 180,
               az = environment.sun.azimuth_deg * M_PI / 180;
  to_sun_ = Eigen::Vector3d(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
  // Stored as E / pi, so that a Lambertian surface of albedo a facing the sun
  // has radiance a * sun_irradiance_ (cd/m^2); the tint has luminance 1.
  const Eigen::Vector3f sun_tint = Eigen::Vector3f(1.0f, 0.96f, 0.9f) / 0.96432f;
  sun_irradiance_ = sun_tint * static_cast<float>(environment.sun.illuminance_lux / M_PI);
  ambient_ = (static_cast<float>(kSkyZenithWeight) * zenith_ +
              static_cast<float>(kSkyHorizonWeight) * horizon_) *
             static_cast<float>(environment.skylight_intensity);
  fog_density_ = environment.fog_density;
  InitClearSky(sky);
  cloud_density_ = std::clamp(sky.cloud_density, 0.0, 1.0);
  const auto& types = CloudTypes();
  if (std::find(types.begin(), types.end(), sky.cloud_type) == types.end()) {
    throw Error("sky: unknown cloud type '" + sky.cloud_type + "'" +
                DidYouMean(sky.cloud_type, types) + "; known: " + Join(types, ", "));
  }
  if (sky.cloud_type == "none") cloud_density_ = 0;
  if (sky.cloud_type == "cumulus") cloud_frequency_ = 1.5, cloud_softness_ = 0.1;
  if (sky.cloud_type == "nimbostratus") cloud_frequency_ = 0.5, cloud_softness_ = 0.5;
  if (sky.cloud_type == "stratus")
    cloud_frequency_ = 0.3, cloud_stretch_ = 3, cloud_softness_ = 0.6;
  if (sky.cloud_type == "cirrus") cloud_frequency_ = 2.0, cloud_stretch_ = 6, cloud_softness_ = 0.3;
  cloud_reuse_distance_ = std::numeric_limits<double>::infinity();
  if (cloud_density_ > 0) {
    InitCloudReuse();
    // Clouds dim the sun (haze; the clouds themselves cast shadows,
    // CloudTransmittance) and whiten the skylight.
    sun_irradiance_ *= static_cast<float>(1 - 0.3 * cloud_density_);
    ambient_ = ambient_ * static_cast<float>(1 - 0.3 * cloud_density_) +
               Eigen::Vector3f::Constant(static_cast<float>(
                   0.2 * sky.luminance_cd_m2 * cloud_density_ * environment.skylight_intensity));
  }
  ground_bounce_ =
      kBounceAlbedo *
      (ambient_ + sun_irradiance_ * static_cast<float>(std::max(0.0, to_sun_.z()) *
                                                       environment.skylight_intensity));
  blocker_bounce_ = kBounceAlbedo * ambient_;
}

void Sky::InitClearSky(const PlannedSky& sky) {
  turbidity_ = std::min(10.0, 2.5 + 1000 * fog_density_);
  const double t = turbidity_;
  // Preetham et al. 1999, appendix A.2: the luminance (Y) distribution.
  perez_[0] = 0.1787 * t - 1.4630;
  perez_[1] = -0.3554 * t + 0.4275;
  perez_[2] = -0.0227 * t + 5.3251;
  perez_[3] = 0.1206 * t - 2.5771;
  perez_[4] = -0.0670 * t + 0.3703;
  zenith_perez_ = Perez(1, std::acos(std::clamp(to_sun_.z(), -1.0, 1.0)));
  air_extinction_ = 3.912 / (80000 / (t - 1));
  zenith_luminance_ = static_cast<float>(sky.luminance_cd_m2);
  const float zl = static_cast<float>(RelativeLuminance(zenith_.cast<double>()));
  const float hl = static_cast<float>(RelativeLuminance(horizon_.cast<double>()));
  zenith_colour_ = zl > 0 ? Eigen::Vector3f(zenith_ / zl) : Eigen::Vector3f::Zero();
  horizon_colour_ = hl > 0 ? Eigen::Vector3f(horizon_ / hl) : Eigen::Vector3f::Zero();
}

double Sky::Perez(double cos_theta, double gamma) const {
  const double c = std::max(cos_theta, 0.01);
  const double cos_gamma = std::cos(gamma);
  return (1 + perez_[0] * std::exp(perez_[1] / c)) *
         (1 + perez_[2] * std::exp(perez_[3] * gamma) + perez_[4] * cos_gamma * cos_gamma);
}

Eigen::Vector3f Sky::ClearSky(const Eigen::Vector3d& d) const {
  const double up = std::clamp(d.z(), 0.0, 1.0);
  const double gamma = std::acos(std::clamp(d.dot(to_sun_), -1.0, 1.0));
  const float luminance = zenith_luminance_ * static_cast<float>(Perez(up, gamma) / zenith_perez_);
  const float t = static_cast<float>(std::sqrt(up));
  // Around the sun the sky whitens (forward scattering is grey).
  const float glow = static_cast<float>(
      0.5 * std::clamp(perez_[2] * std::exp(perez_[3] * gamma) / (1 + perez_[2]), 0.0, 1.0));
  const Eigen::Vector3f colour = (1 - t) * horizon_colour_ + t * zenith_colour_;
  return luminance * ((1 - glow) * colour + glow * Eigen::Vector3f::Ones());
}

double Sky::HazeTransmittance(double distance_m) const {
  return std::exp(-fog_density_ * distance_m -
                  air_extinction_ * std::max(0.0, distance_m - kClearAirM));
}

Eigen::Vector3f Sky::Haze(const Eigen::Vector3d& d) const {
  const double h = std::hypot(d.x(), d.y());
  if (!(h > 0)) return ClearSky(Eigen::Vector3d(1, 0, 0));
  return ClearSky(Eigen::Vector3d(d.x() / h, d.y() / h, 0));
}

void Sky::InitCloudReuse() {
  // The deck's finest wavelength (m): five octaves from cloud_frequency_
  // cycles/km, stretch times finer across y.
  const double finest = 1000 / (cloud_frequency_ * 16 * std::max(1.0, cloud_stretch_));
  // A step of d on the ground moves the sun ray's crossing of the deck by up
  // to d * (1 + cot(elevation)).
  const double along_sun = 1 + std::hypot(to_sun_.x(), to_sun_.y()) / std::max(to_sun_.z(), 0.01);
  // The cover ramps from clear to full over a noise change of
  // cloud_softness_, so the transmittance is kCloudOpacity / cloud_softness_
  // times steeper than the noise.
  cloud_reuse_distance_ = finest / 64 * cloud_softness_ / kCloudOpacity / along_sun;
  // The steepest the deck's noise gets per metre on the ground: each of the
  // five octaves adds the noise's slope bound times its amplitude times its
  // frequency, which is 1 for every octave, over Fbm's norm 1 + 1/2 + ... +
  // 1/16.
  cloud_noise_slope_ = Perlin::kSlopeBound2D * 5 / 1.9375 * cloud_frequency_ *
                       std::max(1.0, cloud_stretch_) / 1000 * along_sun;
}

double Sky::CloudNoiseAt(double x, double y) const {
  return noise_.Fbm(x * cloud_frequency_, y * cloud_frequency_ * cloud_stretch_, 5);
}

double Sky::CloudThreshold() const { return 0.6 - 1.2 * cloud_density_; }

double Sky::CloudCoverAt(double x, double y) const {
  return std::clamp((CloudNoiseAt(x, y) - CloudThreshold()) / cloud_softness_, 0.0, 1.0);
}

double Sky::CloudCover(const Eigen::Vector3d& d) const {
  if (cloud_density_ <= 0 || d.z() <= 0.01) return 0;
  // Where the ray meets a cloud deck 1 km up, in km.
  const double cover = CloudCoverAt(d.x() / d.z(), d.y() / d.z());
  return cover * std::min(1.0, d.z() * 4);  // thin out towards the horizon
}

double Sky::CloudTransmittance(const Eigen::Vector3d& p,
                               double* reuse_distance,
                               double* exact_distance) const {
  double unused_reuse, unused_exact;
  double& reuse = reuse_distance != nullptr ? *reuse_distance : unused_reuse;
  double& exact = exact_distance != nullptr ? *exact_distance : unused_exact;
  reuse = exact = std::numeric_limits<double>::infinity();
  if (cloud_density_ <= 0 || to_sun_.z() <= 0.01) return 1;
  // Where the ray towards the sun crosses the deck, in km.
  const double t = (kCloudDeckM - p.z()) / to_sun_.z();
  reuse = exact = 0;  // at and above the deck: a step in the field
  if (!(t > 0)) return 1;
  const double n = CloudNoiseAt((p.x() + t * to_sun_.x()) / 1000, (p.y() + t * to_sun_.y()) / 1000);
  const double threshold = CloudThreshold();
  // Where the deck is clear (n <= threshold) or full (n >= threshold +
  // softness) with a margin, it stays so, exactly, until the noise has changed
  // by that margin; not past the deck's height, above which the
  // transmittance is 1.
  const double margin = std::max(threshold - n, n - threshold - cloud_softness_);
  if (margin > 0) exact = std::min(margin / cloud_noise_slope_, kCloudDeckM - p.z());
  reuse =
      std::min(std::max(cloud_reuse_distance_, margin / cloud_noise_slope_), kCloudDeckM - p.z());
  return 1 - kCloudOpacity * std::clamp((n - threshold) / cloud_softness_, 0.0, 1.0);
}

double Sky::CloudReuseDistanceInside(const Eigen::Vector3d& p, double remaining) const {
  return std::min(std::max(cloud_reuse_distance_, remaining), kCloudDeckM - p.z());
}

Eigen::Vector3f Sky::Radiance(const Eigen::Vector3d& d) const {
  Eigen::Vector3f sky;
  if (d.z() >= 0) {
    sky = ClearSky(d);
  } else {
    // Below the horizon with no terrain: a hazy floor, darkening smoothly
    // from the horizon's haze to 0.8 of it over 6 degrees, with no seam.
    const float below = static_cast<float>(std::min(1.0, -d.z() / 0.1));
    sky = Haze(d) * (1 - 0.2f * below * below * (3 - 2 * below));
  }
  const double cos_sun = d.dot(to_sun_);
  if (cos_sun > kSunDiscCos) sky += sun_irradiance_ * 20.f;  // the sun's disc
  const double cover = CloudCover(d);
  if (cover > 0) {
    const float c = static_cast<float>(cover);
    const Eigen::Vector3f cloud = horizon_ * 1.1f + sun_irradiance_ * 0.05f;
    sky = (1 - c) * sky + c * cloud;
  }
  return sky;
}

}  // namespace lsds::gen
