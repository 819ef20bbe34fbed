#include "generator/lang/environment.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "libs/util/strings.h"

namespace lsds {
namespace {

double NonNegative(const Node& n, Rng& rng) {
  const double v = SampleScalar(n, rng);
  if (v < 0) n.Fail("expected a value >= 0, sampled " + FormatNumber(v));
  return v;
}

double Fraction(const Node& n, Rng& rng) {
  const double v = SampleScalar(n, rng);
  if (v < 0 || v > 1)
    n.Fail("expected a value in [0, 1], sampled " + FormatNumber(v));
  return v;
}

std::string CloudType(const Node& n, Rng& rng) {
  static const std::vector<std::string> kTypes = {
      "none", "cumulus", "nimbostratus", "cirrus", "stratus"};
  for (const std::string& option : StringOptions(n))
    if (std::find(kTypes.begin(), kTypes.end(), option) == kTypes.end())
      (n->is_object() ? n.Child(option) : n)
          .FailKey("unknown cloud type '" + option + "'" +
                   DidYouMean(option, kTypes));
  return SampleString(n, rng);
}

Eigen::Vector3d Color(const Node& n, Rng& rng) {
  static const std::map<std::string, Eigen::Vector3d> kColors = {
      {"white", {1, 1, 1}},
      {"black", {0, 0, 0}},
      {"gray", {0.5, 0.5, 0.5}},
      {"grey", {0.5, 0.5, 0.5}},
      {"blue", {0.55, 0.7, 0.95}},
      {"red", {0.9, 0.2, 0.15}},
      {"green", {0.3, 0.7, 0.3}},
      {"orange", {1.0, 0.6, 0.2}},
      {"yellow", {1.0, 0.9, 0.3}}};
  if (n->is_string() || n->is_object()) {
    std::vector<std::string> names;
    for (const auto& [name, c] : kColors) names.push_back(name);
    for (const std::string& option : StringOptions(n))
      if (!kColors.count(option))
        (n->is_object() ? n.Child(option) : n)
            .FailKey("unknown color '" + option + "'" +
                     DidYouMean(option, names) +
                     "; use a name or [r, g, b] in [0, 1]");
    return kColors.at(SampleString(n, rng));
  }
  Eigen::Vector3d c = SampleVec3(n, rng);
  if (c.maxCoeff() > 1.0) c /= 255.0;  // 0-255 colours
  if (c.minCoeff() < 0 || c.maxCoeff() > 1)
    n.Fail("colour components must be in [0, 1] (or 0-255)");
  return c;
}

// The atmosphere's extinction coefficient per metre (docs/languages.md,
// "Atmosphere"), from one of: `fog` / `fog_density` (per metre), `density`
// (the paper's fraction of the range from clear air, 0, to a fog of 100 m
// meteorological visibility, 1) or `visibility` (meteorological, metres,
// Koschmieder's 2 % contrast: extinction = 3.912 / visibility).
double AtmosphereExtinction(const Node& b, Rng& rng) {
  constexpr double kKoschmieder = 3.912;
  constexpr double kDensestVisibilityM = 100;  // density 1
  constexpr double kMinVisibilityM = 10;       // anything denser is absurd
  double extinction = 0;
  int given = 0;
  for (const char* key : {"fog", "fogdensity"})
    if (const Node n = b.Find(key)) {
      extinction = NonNegative(n, rng);
      if (extinction > kKoschmieder / kMinVisibilityM)
        n.Fail("fog is an extinction per metre; " + FormatNumber(extinction) +
               " /m means a visibility of " +
               FormatNumber(kKoschmieder / extinction) + " m. Use at most " +
               FormatNumber(kKoschmieder / kMinVisibilityM) +
               " /m, or density (a fraction) or visibility (metres)");
      ++given;
    }
  if (const Node n = b.Find("density")) {
    const double d = NonNegative(n, rng);
    if (d > 1)
      n.Fail(
          "density is a fraction in [0, 1] (1: a fog of 100 m visibility); "
          "write 10 % as 0.1");
    extinction = d * kKoschmieder / kDensestVisibilityM;
    ++given;
  }
  if (const Node n = b.Find("visibility")) {
    const double v = SampleScalar(n, rng);
    if (!(v >= kMinVisibilityM))
      n.Fail(
          "visibility is the meteorological visibility in metres, at least "
          "10");
    extinction = kKoschmieder / v;
    ++given;
  }
  if (given > 1)
    b.Fail(
        "give one of fog (per metre), density (a fraction) or visibility "
        "(metres)");
  return extinction;
}

}  // namespace

bool IsEnvironmentKind(const std::string& kind) {
  return kind == "skybox" || kind == "light" || kind == "atmosphere" ||
         kind == "skylight" || kind == "terrain";
}

const std::vector<std::string>& EnvironmentKeys(const std::string& kind,
                                                bool in_change) {
  static const std::map<std::string, std::vector<std::string>> kKeys = {
      {"skybox",
       {"color", "clouds", "cloud_type", "cloud_density", "intensity"}},
      {"light", {"elevation", "azimuth", "intensity"}},
      {"atmosphere", {"fog", "fog_density", "density", "visibility"}},
      {"skylight", {"intensity"}},
      {"terrain",
       {"size", "height", "perlin", "frequency", "material", "seed"}}};
  static const std::vector<std::string> kTerrainChange = {"material"};
  if (in_change && kind == "terrain") return kTerrainChange;
  return kKeys.at(kind);
}

void ApplyEnvironment(const std::string& kind,
                      const Node& b,
                      Rng& rng,
                      PlannedEnvironment* env) {
  if (kind == "skybox") {
    if (const Node n = b.Find("color")) env->sky.color = Color(n, rng);
    if (const Node n = b.Find("clouds")) {
      n.CheckKeys({"type", "density"}, "clouds");
      if (const Node t = n.Find("type"))
        env->sky.cloud_type = CloudType(t, rng);
      if (const Node d = n.Find("density"))
        env->sky.cloud_density = Fraction(d, rng);
    }
    if (const Node n = b.Find("cloudtype"))
      env->sky.cloud_type = CloudType(n, rng);
    if (const Node n = b.Find("clouddensity"))
      env->sky.cloud_density = Fraction(n, rng);
    if (const Node n = b.Find("intensity"))
      env->sky.intensity = NonNegative(n, rng);
  } else if (kind == "light") {
    if (const Node n = b.Find("elevation")) {
      env->sun.elevation_deg = SampleScalar(n, rng);
      if (std::abs(env->sun.elevation_deg) > 90)
        n.Fail("sun elevation must be within [-90, 90] degrees");
    }
    if (const Node n = b.Find("azimuth"))
      env->sun.azimuth_deg = SampleScalar(n, rng);
    if (const Node n = b.Find("intensity"))
      env->sun.intensity = NonNegative(n, rng);
  } else if (kind == "atmosphere") {
    env->fog_density = AtmosphereExtinction(b, rng);
  } else if (kind == "skylight") {
    if (const Node n = b.Find("intensity"))
      env->skylight_intensity = NonNegative(n, rng);
  } else if (kind == "terrain") {
    if (const Node m = b.Find("material"))
      env->terrain_material = SampleString(m, rng);
  }
}

}  // namespace lsds
