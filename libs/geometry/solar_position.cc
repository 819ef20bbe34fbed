#include "libs/geometry/solar_position.h"

#include <cmath>

namespace lsds {
namespace {

constexpr double kDeg = M_PI / 180.0;

double Wrap360(double degrees) {
  const double wrapped = std::fmod(degrees, 360.0);
  return wrapped < 0 ? wrapped + 360.0 : wrapped;
}

// NOAA's refraction correction (degrees) for a true elevation (degrees).
double Refraction(double elevation_deg) {
  if (elevation_deg > 85.0) return 0.0;
  const double te = std::tan(elevation_deg * kDeg);
  double arcsec;
  if (elevation_deg > 5.0) {
    arcsec = 58.1 / te - 0.07 / (te * te * te) + 0.000086 / std::pow(te, 5);
  } else if (elevation_deg > -0.575) {
    arcsec = 1735.0 + elevation_deg *
                          (-518.2 + elevation_deg *
                                        (103.4 + elevation_deg * (-12.79 + elevation_deg * 0.711)));
  } else {
    arcsec = -20.774 / te;
  }
  return arcsec / 3600.0;
}

}  // namespace

double UnixSeconds(
    int year, int month, int day, int hour, int minute, double second, double utc_offset_hours) {
  // Howard Hinnant's days_from_civil.
  const int y = year - (month <= 2 ? 1 : 0);
  const int era = (y >= 0 ? y : y - 399) / 400;
  const int yoe = y - era * 400;
  const int mp = (month + 9) % 12;
  const int doy = (153 * mp + 2) / 5 + day - 1;
  const int doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  const double days = static_cast<double>(era) * 146097 + doe - 719468;
  return days * 86400.0 + hour * 3600.0 + minute * 60.0 + second - utc_offset_hours * 3600.0;
}

SolarPosition SunPositionAt(double unix_seconds, double latitude_deg, double longitude_deg) {
  const double julian_day = unix_seconds / 86400.0 + 2440587.5;
  const double t = (julian_day - 2451545.0) / 36525.0;                       // Julian centuries
  const double l0 = Wrap360(280.46646 + t * (36000.76983 + t * 0.0003032));  // mean long.
  const double m = 357.52911 + t * (35999.05029 - 0.0001537 * t);            // anomaly
  const double e = 0.016708634 - t * (0.000042037 + 0.0000001267 * t);
  const double c = std::sin(m * kDeg) * (1.914602 - t * (0.004817 + 0.000014 * t)) +
                   std::sin(2 * m * kDeg) * (0.019993 - 0.000101 * t) +
                   std::sin(3 * m * kDeg) * 0.000289;
  const double true_longitude = l0 + c;
  const double omega = 125.04 - 1934.136 * t;
  const double apparent_longitude = true_longitude - 0.00569 - 0.00478 * std::sin(omega * kDeg);
  const double mean_obliquity =
      23.0 + (26.0 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60.0) / 60.0;
  const double obliquity = mean_obliquity + 0.00256 * std::cos(omega * kDeg);
  const double declination =
      std::asin(std::sin(obliquity * kDeg) * std::sin(apparent_longitude * kDeg));
  const double y = std::pow(std::tan(obliquity * kDeg / 2), 2);
  const double equation_of_time_min =
      4.0 / kDeg *
      (y * std::sin(2 * l0 * kDeg) - 2 * e * std::sin(m * kDeg) +
       4 * e * y * std::sin(m * kDeg) * std::cos(2 * l0 * kDeg) -
       0.5 * y * y * std::sin(4 * l0 * kDeg) - 1.25 * e * e * std::sin(2 * m * kDeg));
  const double utc_minutes = std::fmod(unix_seconds, 86400.0) / 60.0;
  const double true_solar_minutes =
      std::fmod(utc_minutes + equation_of_time_min + 4.0 * longitude_deg, 1440.0);
  double hour_angle = true_solar_minutes / 4.0 - 180.0;
  if (hour_angle < -180) hour_angle += 360;
  const double lat = latitude_deg * kDeg, ha = hour_angle * kDeg;
  const double cos_zenith =
      std::sin(lat) * std::sin(declination) + std::cos(lat) * std::cos(declination) * std::cos(ha);
  const double zenith = std::acos(std::max(-1.0, std::min(1.0, cos_zenith)));
  const double azimuth =
      std::atan2(std::sin(ha),
                 std::cos(ha) * std::sin(lat) - std::tan(declination) * std::cos(lat)) /
          kDeg +
      180.0;
  SolarPosition position;
  position.azimuth_deg = Wrap360(azimuth);
  const double elevation = 90.0 - zenith / kDeg;
  position.elevation_deg = elevation + Refraction(elevation);
  return position;
}

}  // namespace lsds
