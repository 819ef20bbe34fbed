// Solar position against the NREL SPA reference case and WGS84 conversions
// against GeographicLib's own round trip and an arc-length check.
#include <gtest/gtest.h>

#include <cmath>

#include "libs/geometry/geodesy.h"
#include "libs/geometry/solar_position.h"

namespace lsds {
namespace {

TEST(SolarPosition, MatchesTheSpaReferenceCaseWithinATenthOfADegree) {
  // Reda & Andreas, "Solar Position Algorithm for Solar Radiation
  // Applications" (NREL/TP-560-34302, 2008), table A4.1: 2003-10-17
  // 12:30:30 local (UTC-7) at 39.742476 N, 105.1786 W: topocentric zenith
  // 50.11162 deg (refraction included), azimuth 194.34024 deg from north.
  const double utc = UnixSeconds(2003, 10, 17, 12, 30, 30, -7);
  const SolarPosition sun = SunPositionAt(utc, 39.742476, -105.1786);
  EXPECT_NEAR(90.0 - sun.elevation_deg, 50.11162, 0.1);
  EXPECT_NEAR(sun.azimuth_deg, 194.34024, 0.1);
}

TEST(SolarPosition, NoonSunIsDueSouthAndHighestAtTheSolstice) {
  // Greenwich, June solstice 2026 (21 June), around 12:01:40 UTC.
  double best_elevation = -90, best_azimuth = 0;
  for (int minute = 0; minute < 240; ++minute) {
    const SolarPosition sun =
        SunPositionAt(UnixSeconds(2026, 6, 21, 10, minute, 0, 0), 51.4779, 0.0);
    if (sun.elevation_deg > best_elevation)
      best_elevation = sun.elevation_deg, best_azimuth = sun.azimuth_deg;
  }
  // 90 - latitude + obliquity (23.44), plus a little refraction.
  EXPECT_NEAR(best_elevation, 90 - 51.4779 + 23.44, 0.1);
  EXPECT_NEAR(best_azimuth, 180.0, 0.5);
}

TEST(UnixSeconds, KnowsTheEpochAndLeapYears) {
  EXPECT_EQ(UnixSeconds(1970, 1, 1, 0, 0, 0, 0), 0.0);
  EXPECT_EQ(UnixSeconds(2000, 3, 1, 0, 0, 0, 0), 951868800.0);
  EXPECT_EQ(UnixSeconds(2024, 2, 29, 12, 0, 0, 2), 1709200800.0);
}

TEST(Geodesy, RoundTripsAndAMetreNorthIsAnArcOfTheMeridian) {
  const GeoOrigin origin{47.3769, 8.5417, 408};  // Zurich
  const Eigen::Vector3d point(250, -1200, 35);
  const Geodetic g = GeodeticOf(origin, point);
  EXPECT_LT((EnuOf(origin, g) - point).norm(), 1e-6);
  // 1 km north: the meridian arc at 47.4 deg is about 111,195 m per degree.
  const Geodetic north = GeodeticOf(origin, {0, 1000, 0});
  EXPECT_NEAR((north.latitude_deg - origin.latitude_deg) * 111195.0, 1000, 2);
  EXPECT_NEAR(north.longitude_deg, origin.longitude_deg, 1e-9);
  // The tangent plane falls away from the ellipsoid: 1 km out is ~8 cm lower.
  EXPECT_NEAR(north.altitude_msl_m - origin.altitude_m, 0.0785, 0.01);
}

}  // namespace
}  // namespace lsds
