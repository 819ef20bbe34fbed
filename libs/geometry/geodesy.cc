#include "libs/geometry/geodesy.h"

#include <GeographicLib/LocalCartesian.hpp>

namespace lsds {

Geodetic GeodeticOf(const GeoOrigin& origin, const Eigen::Vector3d& point_in_enu) {
  // The origin's MSL altitude stands in for its ellipsoidal height: only
  // height differences matter below.
  const GeographicLib::LocalCartesian local(
      origin.latitude_deg, origin.longitude_deg, origin.altitude_m);
  Geodetic g;
  local.Reverse(point_in_enu.x(),
                point_in_enu.y(),
                point_in_enu.z(),
                g.latitude_deg,
                g.longitude_deg,
                g.altitude_msl_m);
  return g;
}

Eigen::Vector3d EnuOf(const GeoOrigin& origin, const Geodetic& position) {
  const GeographicLib::LocalCartesian local(
      origin.latitude_deg, origin.longitude_deg, origin.altitude_m);
  Eigen::Vector3d p;
  local.Forward(
      position.latitude_deg, position.longitude_deg, position.altitude_msl_m, p.x(), p.y(), p.z());
  return p;
}

}  // namespace lsds
