#include "perturb/noise_spec.h"

#include <cmath>
#include <sstream>

#include "libs/util/error.h"

namespace lsds::noise {

const char* FieldName(int field) {
  static const char* const names[kFieldCount] = {
      "east_m", "north_m", "up_m", "roll_deg", "pitch_deg", "yaw_deg", "time_s", "hfov_deg"};
  return field >= 0 && field < kFieldCount ? names[field] : "?";
}

namespace {
// The command-line flag that sets each field, for messages.
const char* FieldFlag(int field) {
  static const char* const flags[kFieldCount] = {"--sigma-pos",
                                                 "--sigma-pos",
                                                 "--sigma-alt",
                                                 "--sigma-rot",
                                                 "--sigma-rot",
                                                 "--sigma-rot",
                                                 "--sigma-time",
                                                 "--sigma-fov"};
  return flags[field];
}
}  // namespace

void NoiseSpec::Validate() const {
  for (int f = 0; f < kFieldCount; ++f) {
    if (!std::isfinite(sigma[f]) || sigma[f] < 0) {
      std::ostringstream message;
      message << FieldFlag(f) << ": sigma of " << FieldName(f) << " must be finite and >= 0, got "
              << sigma[f];
      throw Error(message.str());
    }
    if (!std::isfinite(bias[f])) {
      throw Error(std::string("--bias: bias of ") + FieldName(f) + " must be finite");
    }
  }
  if (model == NoiseModel::kGaussMarkov) {
    if (!std::isfinite(tau) || tau <= 0) {
      throw Error(
          "--tau: the gauss-markov model needs a correlation time tau > 0 "
          "seconds");
    }
  } else if (tau != 0) {
    throw Error(std::string("--tau applies only to --model gauss-markov, not ") +
                NoiseModelName(model));
  }
}

bool NoiseSpec::IsZero() const {
  for (int f = 0; f < kFieldCount; ++f) {
    if (sigma[f] != 0 || bias[f] != 0) return false;
  }
  return true;
}

nlohmann::json NoiseSpec::ParametersJson(const WorldFrame& world) const {
  nlohmann::json sigmas = nlohmann::json::object();
  nlohmann::json biases = nlohmann::json::object();
  for (int f = 0; f < kFieldCount; ++f) {
    sigmas[FieldName(f)] = sigma[f];
    biases[FieldName(f)] = bias[f];
  }
  nlohmann::json parameters = {
      {"sigma", sigmas},
      {"bias", biases},
      {"world_frame", world.name},
      {"position_axes",
       "east, north, up in metres, mapped into the declared world frame and "
       "unit"},
      {"rotation_axes",
       "rotation vector about the heading-level axes forward, right, down "
       "(roll, pitch, yaw) in "
       "degrees, composed on the left of the true ned_from_body"},
      {"hfov", "horizontal field of view in degrees; principal point and aspect kept"},
  };
  if (model == NoiseModel::kUniform) {
    parameters["distribution"] = "uniform on [-sqrt(3) sigma, sqrt(3) sigma] per field";
  } else if (model == NoiseModel::kGaussMarkov) {
    parameters["tau_s"] = tau;
    parameters["distribution"] =
        "first-order Gauss-Markov, stationary std sigma, autocorrelation "
        "exp(-dt / tau)";
  } else {
    parameters["distribution"] = "i.i.d. normal with std sigma per field";
  }
  return parameters;
}

std::string NoiseSpec::Describe() const {
  std::ostringstream text;
  text << "perturbed: " << NoiseModelName(model) << ", seed " << seed << ", sigma pos "
       << sigma[kEast] << " m, alt " << sigma[kUp] << " m, rot " << sigma[kRoll] << "/"
       << sigma[kPitch] << "/" << sigma[kYaw] << " deg";
  if (sigma[kTime] != 0) text << ", time " << sigma[kTime] << " s";
  if (sigma[kHfov] != 0) text << ", hfov " << sigma[kHfov] << " deg";
  bool any_bias = false;
  for (int f = 0; f < kFieldCount; ++f) any_bias = any_bias || bias[f] != 0;
  if (any_bias) text << ", with bias";
  if (model == NoiseModel::kGaussMarkov) text << ", tau " << tau << " s";
  return text.str();
}

}  // namespace lsds::noise
