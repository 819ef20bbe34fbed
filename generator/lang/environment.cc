#include "generator/lang/environment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "generator/lang/scene/ground.h"
#include "generator/lang/vocabulary.h"
#include "libs/geometry/solar_position.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

// A sampled number of `kind`'s key `key`, within the table's range.
double Sampled(const Node& n, const char* kind, const char* key, Rng& rng) {
  return SampleInRange(n, KindVocabulary(kind).Key(key), rng);
}

std::string CloudType(const Node& n, Rng& rng) {
  static const std::vector<std::string> kTypes = {
      "none", "cumulus", "nimbostratus", "cirrus", "stratus"};
  for (const std::string& option : StringOptions(n))
    if (std::find(kTypes.begin(), kTypes.end(), option) == kTypes.end())
      (n->is_object() ? n.Child(option) : n)
          .FailKey("unknown cloud type '" + option + "'" + DidYouMean(option, kTypes));
  return SampleString(n, rng);
}

Eigen::Vector3d Color(const Node& n, Rng& rng) {
  static const std::map<std::string, Eigen::Vector3d> kColors = {{"white", {1, 1, 1}},
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
    names.reserve(kColors.size());
    for (const auto& [name, c] : kColors) names.push_back(name);
    for (const std::string& option : StringOptions(n))
      if (!kColors.count(option))
        (n->is_object() ? n.Child(option) : n)
            .FailKey("unknown color '" + option + "'" + DidYouMean(option, names) +
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
  const KindSpec& kind = KindVocabulary("atmosphere");
  double extinction = 0;
  int given = 0;
  if (const Node n = FindKey(b, kind, "fog")) {
    extinction = SampleInRange(n, kind.Key("fog"), rng);
    ++given;
  }
  if (const Node n = FindKey(b, kind, "density")) {
    extinction = SampleInRange(n, kind.Key("density"), rng) * kKoschmieder / kDensestVisibilityM;
    ++given;
  }
  if (const Node n = FindKey(b, kind, "visibility")) {
    extinction = kKoschmieder / SampleInRange(n, kind.Key("visibility"), rng);
    ++given;
  }
  if (given > 1)
    b.Fail(
        "give one of fog (per metre), density (a fraction) or visibility "
        "(metres)");
  return extinction;
}

// "HH:MM" or "HH:MM:SS" (local) as seconds since midnight, checked at `where`; the parts too.
double LocalSeconds(const Node& where,
                    const std::string& text,
                    int* hour_out = nullptr,
                    int* minute_out = nullptr,
                    double* second_out = nullptr) {
  int hour = 0, minute = 0;
  double second = 0;
  const int n = std::sscanf(text.c_str(), "%d:%d:%lf", &hour, &minute, &second);
  if (n < 2 || hour < 0 || hour > 24 || minute < 0 || minute > 59 || second < 0 || second >= 61)
    where.Fail("time is \"HH:MM\" or \"HH:MM:SS\" (local), not '" + text + "'");
  if (hour_out) *hour_out = hour, *minute_out = minute, *second_out = second;
  return hour * 3600.0 + minute * 60.0 + second;
}

// `time:["08:00", "17:00"]`: two local times, an interval of the time of day.
bool IsTimeInterval(const Node& time) {
  return time->is_array() && time->size() == 2 && time.Item(0)->is_string() &&
         time.Item(1)->is_string();
}

// `date:"2026-06-21"`, `time:"14:30"` (or "14:30:15", or an interval ["08:00","17:00"]),
// `utc_offset:2`: the sun by date and local time. A time alone keeps the date of the clock in
// force.
void SunClock(const Node& b, Rng& rng, PlannedSun* sun) {
  const Node date = b.Find("date"), time = b.Find("time"), offset = b.Find("utcoffset");
  if (!date && !time && !offset) return;
  if (offset) {
    sun->utc_offset_h = Sampled(offset, "light", "utc_offset", rng);
  }
  int year = 0, month = 0, day = 0;
  if (date) {
    const std::string text = SampleString(date, rng);
    if (std::sscanf(text.c_str(), "%d-%d-%d", &year, &month, &day) != 3 || month < 1 ||
        month > 12 || day < 1 || day > 31)
      date.Fail("date is \"YYYY-MM-DD\", not '" + text + "'");
  } else if (sun->clock_utc_s) {
    // The local date of the clock in force.
    const double local_days = std::floor((*sun->clock_utc_s + sun->utc_offset_h * 3600) / 86400);
    int y = 1970, m = 1, d = 1;
    // Civil from days (Howard Hinnant's algorithm).
    int64_t z = static_cast<int64_t>(local_days) + 719468;
    const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
    const int64_t doe = z - era * 146097;
    const int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    const int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    const int64_t mp = (5 * doy + 2) / 153;
    d = static_cast<int>(doy - (153 * mp + 2) / 5 + 1);
    m = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
    y = static_cast<int>(yoe + era * 400 + (m <= 2 ? 1 : 0));
    year = y, month = m, day = d;
  } else {
    (time ? time : offset).Fail("a sun by local time needs a date too");
  }
  int hour = 12, minute = 0;
  double second = 0;
  if (time && IsTimeInterval(time)) {
    // A time-of-day interval ["HH:MM", "HH:MM"]: a local time drawn uniformly between the two.
    const double lo = LocalSeconds(time.Item(0), ReadString(time.Item(0)));
    const double hi = LocalSeconds(time.Item(1), ReadString(time.Item(1)));
    if (hi < lo) time.Fail("a time interval runs forward in one day: [\"06:00\", \"18:00\"]");
    hour = minute = 0;
    second = rng.Uniform(lo, hi);
  } else if (time) {
    const std::string text = SampleString(time, rng);
    LocalSeconds(time, text, &hour, &minute, &second);
  }
  sun->clock_utc_s = UnixSeconds(year, month, day, hour, minute, second, sun->utc_offset_h);
}

}  // namespace

bool IsEnvironmentKind(const std::string& kind) {
  return kind == "skybox" || kind == "light" || kind == "atmosphere" || kind == "skylight" ||
         kind == "terrain";
}

std::vector<std::string> EnvironmentKeys(const std::string& kind, bool in_change) {
  return KindVocabulary(kind).Spellings(in_change);
}

// One branch per environment kind (docs/architecture.md, "Long functions").
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
void ApplyEnvironment(const std::string& kind, const Node& b, Rng& rng, PlannedEnvironment* env) {
  if (kind == "skybox") {
    if (const Node n = b.Find("color")) env->sky.color = Color(n, rng);
    if (const Node n = b.Find("clouds")) {
      CheckKeys(n, KindVocabulary("clouds"), "clouds");
      if (const Node t = n.Find("type")) env->sky.cloud_type = CloudType(t, rng);
      if (const Node d = n.Find("density"))
        env->sky.cloud_density = Sampled(d, "clouds", "density", rng);
    }
    if (const Node n = b.Find("cloudtype")) env->sky.cloud_type = CloudType(n, rng);
    if (const Node n = b.Find("clouddensity"))
      env->sky.cloud_density = Sampled(n, "skybox", "cloud_density", rng);
    // `luminance`: the zenith's, cd/m^2. `intensity`: lux on the ground from the sky, as the
    // paper's Table 2 (docs/languages.md, "Light units").
    const Node luminance = b.Find("luminance"), intensity = b.Find("intensity");
    if (luminance && intensity)
      b.Fail("give the sky's luminance (cd/m^2) or its intensity (lux), not both");
    if (luminance) env->sky.luminance_cd_m2 = Sampled(luminance, "skybox", "luminance", rng);
    if (intensity) {
      const double lux = Sampled(intensity, "skybox", "intensity", rng);
      const double lux_per_nit = SkyLuxPerZenithNit(env->sky.color);
      if (lux > 0 && !(lux_per_nit > 0))
        intensity.Fail("a black sky gives no light: give it a colour, or intensity 0");
      env->sky.luminance_cd_m2 = lux > 0 ? lux / lux_per_nit : 0;
    }
  } else if (kind == "light") {
    SunClock(b, rng, &env->sun);
    if (const Node n = b.Find("elevation")) {
      env->sun.elevation_deg = Sampled(n, "light", "elevation", rng);
    }
    if (const Node n = b.Find("azimuth")) env->sun.azimuth_deg = SampleScalar(n, rng);
    // Lux, both (the paper's Table 2): a dusk sun of 50 lux is 50 lux.
    const Node illuminance = b.Find("illuminance"), intensity = b.Find("intensity");
    if (illuminance && intensity) b.Fail("give the sun's illuminance or its intensity, not both");
    if (illuminance) env->sun.illuminance_lux = Sampled(illuminance, "light", "illuminance", rng);
    if (intensity) env->sun.illuminance_lux = Sampled(intensity, "light", "intensity", rng);
  } else if (kind == "atmosphere") {
    env->fog_density = AtmosphereExtinction(b, rng);
  } else if (kind == "skylight") {
    if (const Node n = b.Find("intensity"))
      env->skylight_intensity = Sampled(n, "skylight", "intensity", rng);
  } else if (kind == "terrain") {
    // The shape first, as the scene reads it (its draws come before the material's).
    ReadTerrainShape(b, rng, &env->terrain_shape);
    if (const Node m = b.Find("material")) env->terrain_material = SampleString(m, rng);
  }
}

std::vector<std::string> ImplausibleLight(const std::string& kind,
                                          const Node& b,
                                          const PlannedEnvironment& env) {
  std::vector<std::string> out;
  auto warn = [&](const char* key, const std::string& message) {
    const Node n = b.Find(key);
    out.push_back(n.Where().ToString() + ": " + message);
  };
  char value[64];
  if (kind == "light" && (b.Find("intensity") || b.Find("illuminance"))) {
    const char* key = b.Find("intensity") ? "intensity" : "illuminance";
    const double lux = env.sun.illuminance_lux;
    std::snprintf(value, sizeof value, "%.6g lux", lux);
    if (lux < 100 && env.sun.elevation_deg > 10)
      warn(key,
           std::string("a sun of ") + value +
               " high in the sky is darker than dusk; light is in lux (a clear noon 100000); "
               "scenes written for the old unitless scale meant pi x 10^4 lux per unit");
    if (lux > 150000)
      warn(key,
           std::string("a sun of ") + value +
               " is brighter than sunlight above the atmosphere (about 130000 lux)");
  }
  if (kind == "skybox" && (b.Find("intensity") || b.Find("luminance"))) {
    const double nits = env.sky.luminance_cd_m2;
    const double lux = nits * SkyLuxPerZenithNit(env.sky.color);
    std::snprintf(value, sizeof value, "%.6g lux (zenith %.6g cd/m^2)", lux, nits);
    if (lux > 60000 || nits > 30000)
      warn(b.Find("intensity") ? "intensity" : "luminance",
           std::string("a sky giving ") + value +
               " is brighter than any daylight sky (a clear sky gives 10000-25000 lux)");
  }
  return out;
}

void PlaceSun(const GeoOrigin& geo, double time_s, PlannedSun* sun) {
  if (!sun->clock_utc_s) return;
  const SolarPosition at =
      SunPositionAt(*sun->clock_utc_s + time_s, geo.latitude_deg, geo.longitude_deg);
  sun->azimuth_deg = at.azimuth_deg;
  sun->elevation_deg = at.elevation_deg;
}

}  // namespace lsds
