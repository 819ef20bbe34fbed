// The world frame's place on Earth: a local ENU frame (x east, y north, z up,
// metres) at a WGS84 origin, converted with GeographicLib's LocalCartesian.
#pragma once

#include <Eigen/Core>

namespace lsds {

struct GeoOrigin {
  double latitude_deg = 0;   // WGS84, north
  double longitude_deg = 0;  // WGS84, east
  double altitude_m = 0;     // of the world origin, above mean sea level
};

struct Geodetic {
  double latitude_deg = 0;
  double longitude_deg = 0;
  // Above mean sea level: the origin's altitude plus the height gained on the
  // ellipsoid (the geoid undulation is taken as constant over the scene).
  double altitude_msl_m = 0;
};

// The geodetic position of a point of the ENU world frame (metres).
Geodetic GeodeticOf(const GeoOrigin& origin, const Eigen::Vector3d& point_in_enu);
// The inverse: the ENU point of a geodetic position.
Eigen::Vector3d EnuOf(const GeoOrigin& origin, const Geodetic& position);

}  // namespace lsds
