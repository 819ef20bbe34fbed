// Where the sun is, seen from a place on Earth at a moment: NOAA's solar
// position algorithm (the equations of the NOAA Solar Calculator, after
// Meeus, "Astronomical Algorithms", 1991), with NOAA's approximation of
// atmospheric refraction. Accurate to about 0.01 degree between 1800 and
// 2100, well inside the 0.1 degree a rendered sun needs (docs/languages.md,
// "Time of day and place").
#pragma once

namespace lsds {

struct SolarPosition {
  double azimuth_deg = 0;    // from north, clockwise (east = 90)
  double elevation_deg = 0;  // above the horizon, refraction included
};

// `unix_seconds` is UTC (seconds since 1970-01-01T00:00:00Z); latitude north
// and longitude east in degrees (WGS84).
SolarPosition SunPositionAt(double unix_seconds, double latitude_deg, double longitude_deg);

// Seconds since the epoch of a civil date and time at `utc_offset_hours`
// (e.g. -7 for MST): days from civil (proleptic Gregorian calendar).
double UnixSeconds(
    int year, int month, int day, int hour, int minute, double second, double utc_offset_hours);

}  // namespace lsds
