#include "perturb/metadata_perturber.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include "libs/collection/json_io.h"
#include "libs/util/error.h"

namespace lsds::noise {

namespace {
constexpr double kPi = 3.14159265358979323846;
double Rad(double deg) { return deg * kPi / 180.0; }
}  // namespace

Attitude RotateAttitude(const Attitude& truth, const Eigen::Vector3d& rotation_vector_deg) {
  const double angle = Rad(rotation_vector_deg.norm());
  if (angle == 0.0) return truth;
  // Heading-level axes: north/east/down turned about down by the true yaw.
  const Eigen::Matrix3d ned_from_level =
      Eigen::AngleAxisd(Rad(truth.yaw_deg), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d axis_in_ned = ned_from_level * rotation_vector_deg.normalized();
  const Eigen::Quaterniond measured_ned_from_body =
      Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis_in_ned)) * NedFromBody(truth);
  return AttitudeFromNedFromBody(measured_ned_from_body.normalized());
}

MetadataPerturber::MetadataPerturber(const NoiseSpec& spec, const WorldFrame& world)
    : spec_(spec), world_(world) {
  spec_.Validate();
  processes_.reserve(kFieldCount);
  for (int f = 0; f < kFieldCount; ++f) {
    processes_.emplace_back(
        spec_.model, spec_.sigma[f], spec_.tau, spec_.seed, static_cast<uint64_t>(f));
  }
}

RealizedError MetadataPerturber::NextError(int64_t frame_index, double time) {
  RealizedError error;
  for (int f = 0; f < kFieldCount; ++f) {
    const double noise = processes_[f].Next(frame_index, time);
    error.value[f] = spec_.bias[f] == 0.0 ? noise : spec_.bias[f] + noise;
  }
  return error;
}

MetadataFrame MetadataPerturber::Apply(const MetadataFrame& truth,
                                       const RealizedError& error) const {
  MetadataFrame measured = truth;
  // Position: east/north/up metres into the declared frame and unit (a linear
  // map, so zero stays zero).
  const Eigen::Vector3d position_error = world_.WorldFromEnuMetres(error.position_enu_m());
  for (int i = 0; i < 3; ++i) {
    if (position_error[i] != 0.0) measured.position[i] = truth.position[i] + position_error[i];
  }
  // The survey fields move with the position error: the GNSS fix by the ENU
  // error at the true place, the height above ground by its up part. GSD and
  // footprint are derived from the true pose, not measured: a perturbed
  // variant leaves them out.
  if (truth.geo)
    measured.geo = GeodeticOf(
        GeoOrigin{truth.geo->latitude_deg, truth.geo->longitude_deg, truth.geo->altitude_msl_m},
        error.position_enu_m());
  if (truth.altitude_agl_m)
    measured.altitude_agl_m = *truth.altitude_agl_m + error.position_enu_m().z();
  measured.gsd_m.reset();
  measured.footprint.clear();
  measured.attitude = RotateAttitude(truth.attitude, error.rotation_vector_deg());
  if (error.value[kTime] != 0.0) measured.time = truth.time + error.value[kTime];
  if (error.value[kHfov] != 0.0) {
    const double hfov = truth.camera.HorizontalFovDeg() + error.value[kHfov];
    if (!(hfov > 0.0 && hfov < 180.0)) {
      std::ostringstream message;
      message << "field-of-view noise of " << error.value[kHfov]
              << " deg gives a horizontal field of view of " << hfov
              << " deg, outside (0, 180); lower --sigma-fov or the fov bias";
      Location where;
      where.frame = truth.index;
      throw Error(message.str(), where);
    }
    const double fx = 0.5 * truth.camera.width / std::tan(0.5 * Rad(hfov));
    measured.camera.fy = truth.camera.fy * (fx / truth.camera.fx);
    measured.camera.fx = fx;
  }
  measured.error = {
      {"position", Vector3ToJson(position_error)},
      {"position_enu_m", Vector3ToJson(error.position_enu_m())},
      {"rotation_deg", error.rotation_angle_deg()},
      {"rotation_vector_deg", Vector3ToJson(error.rotation_vector_deg())},
      {"time_s", error.value[kTime]},
      {"hfov_deg", error.value[kHfov]},
  };
  return measured;
}

void ErrorStatistics::Running::Add(double x) {
  ++n;
  const double delta = x - mean;
  mean += delta / static_cast<double>(n);
  m2 += delta * (x - mean);
  sum_squares += x * x;
  max_abs = std::max(max_abs, std::abs(x));
}

nlohmann::json ErrorStatistics::Running::ToJson() const {
  const double std_dev = n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1)) : 0.0;
  const double rms = n > 0 ? std::sqrt(sum_squares / static_cast<double>(n)) : 0.0;
  return {{"mean", mean}, {"std", std_dev}, {"rms", rms}, {"max_abs", max_abs}};
}

void ErrorStatistics::Add(const RealizedError& error) {
  ++count_;
  for (int f = 0; f < kFieldCount; ++f) fields_[f].Add(error.value[f]);
  const Eigen::Vector3d p = error.position_enu_m();
  position_.Add(p.norm());
  horizontal_.Add(std::hypot(p.x(), p.y()));
  rotation_.Add(error.rotation_angle_deg());
}

nlohmann::json ErrorStatistics::ToJson() const {
  nlohmann::json fields = nlohmann::json::object();
  for (int f = 0; f < kFieldCount; ++f) fields[FieldName(f)] = fields_[f].ToJson();
  return {{"frames", count_},
          {"fields", fields},
          {"position_m", position_.ToJson()},
          {"horizontal_m", horizontal_.ToJson()},
          {"rotation_deg", rotation_.ToJson()}};
}

}  // namespace lsds::noise
