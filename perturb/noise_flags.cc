#include "perturb/noise_flags.h"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::noise {

namespace {

std::vector<double> ParseNumbers(const std::string& text, const std::string& flag) {
  std::vector<double> numbers;
  for (const std::string& part : Split(text, ',')) {
    const char* begin = part.c_str();
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(begin, &end);
    if (part.empty() || end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
      throw Error(flag + ": '" + part + "' is not a number (in '" + text + "')");
    }
    numbers.push_back(value);
  }
  return numbers;
}

// Sets fields [first, first + count) from `text`: one value for all of them or
// one per field.
void SetFields(std::array<double, kFieldCount>* values,
               int first,
               int count,
               const std::string& text,
               const std::string& flag) {
  const std::vector<double> numbers = ParseNumbers(text, flag);
  if (numbers.size() != 1 && static_cast<int>(numbers.size()) != count) {
    throw Error(flag + ": expected 1" + (count > 1 ? " or " + std::to_string(count) : "") +
                " value(s), got " + std::to_string(numbers.size()) + " in '" + text + "'");
  }
  for (int i = 0; i < count; ++i)
    (*values)[first + i] = numbers.size() == 1 ? numbers[0] : numbers[i];
}

// --bias FIELD=VALUE[,VALUE...]
void ParseBias(const std::string& text, std::array<double, kFieldCount>* bias) {
  struct Target {
    const char* name;
    int first;
    int count;
  };
  static const Target targets[] = {{"pos", kEast, 2},
                                   {"alt", kUp, 1},
                                   {"rot", kRoll, 3},
                                   {"time", kTime, 1},
                                   {"fov", kHfov, 1},
                                   {"east", kEast, 1},
                                   {"north", kNorth, 1},
                                   {"up", kUp, 1},
                                   {"roll", kRoll, 1},
                                   {"pitch", kPitch, 1},
                                   {"yaw", kYaw, 1}};
  const size_t equals = text.find('=');
  std::vector<std::string> names;
  for (const Target& target : targets) names.push_back(target.name);
  if (equals == std::string::npos) {
    throw Error("--bias: expected FIELD=VALUE (FIELD one of " + Join(names, ", ") + "), got '" +
                text + "'");
  }
  const std::string name = text.substr(0, equals);
  for (const Target& target : targets) {
    if (name == target.name) {
      SetFields(bias, target.first, target.count, text.substr(equals + 1), "--bias " + name);
      return;
    }
  }
  throw Error("--bias: unknown field '" + name + "'" + DidYouMean(name, names) +
              "; expected one of " + Join(names, ", "));
}

}  // namespace

NoiseSpec NoiseSpecFromFlags(const NoiseFlags& flags) {
  NoiseSpec spec;
  spec.model = ParseNoiseModel(flags.model);
  spec.tau = flags.tau;
  spec.seed = flags.seed;
  if (!flags.sigma.empty()) {
    const std::vector<double> values = ParseNumbers(flags.sigma, "--sigma");
    if (values.size() > 2)
      throw Error("--sigma: expected POS_M[,ROT_DEG], got '" + flags.sigma + "'");
    spec.sigma[kEast] = spec.sigma[kNorth] = spec.sigma[kUp] = values[0];
    if (values.size() == 2) spec.sigma[kRoll] = spec.sigma[kPitch] = spec.sigma[kYaw] = values[1];
  }
  if (flags.sigma_pos) spec.sigma[kEast] = spec.sigma[kNorth] = *flags.sigma_pos;
  if (flags.sigma_alt) spec.sigma[kUp] = *flags.sigma_alt;
  if (!flags.sigma_rot.empty()) SetFields(&spec.sigma, kRoll, 3, flags.sigma_rot, "--sigma-rot");
  if (flags.sigma_time) spec.sigma[kTime] = *flags.sigma_time;
  if (flags.sigma_fov) spec.sigma[kHfov] = *flags.sigma_fov;
  for (const std::string& bias : flags.biases) ParseBias(bias, &spec.bias);
  const bool any_noise = !flags.biases.empty() || !flags.sigma.empty() || flags.sigma_pos ||
                         flags.sigma_alt || !flags.sigma_rot.empty() || flags.sigma_time ||
                         flags.sigma_fov;
  if (!any_noise)
    throw Error("no noise given: pass --sigma POS_M[,ROT_DEG], a --sigma-* flag or --bias");
  return spec;
}

std::string DescribePerturbResult(const PerturbResult& result, const NoiseSpec& spec) {
  // The summaries are the statistics objects of metadata_perturber.h and
  // projection_report.h (ToJson), as written into the output and the report.
  const nlohmann::json& position = result.summary["position_m"];
  const nlohmann::json& rotation = result.summary["rotation_deg"];
  std::ostringstream out;
  out << "wrote " << result.output.string() << ": " << result.frames << " frames, "
      << spec.Describe() << "\n"
      << "  position error rms " << position["rms"].get<double>() << " m (max "
      << position["max_abs"].get<double>() << "), rotation error rms "
      << rotation["rms"].get<double>() << " deg (max " << rotation["max_abs"].get<double>()
      << ")\n";
  if (result.registered_as.empty()) {
    out << "  not registered in collection.json: the output is outside the collection\n";
  } else {
    out << "  registered in collection.json as metadata variant '" << result.registered_as << "'\n";
  }
  if (result.report_summary) {
    const nlohmann::json& r = *result.report_summary;
    out << "report " << result.report->string() << ": " << r["corners"].get<int64_t>()
        << " target corners in " << r["frames_with_targets"].get<int64_t>() << " frames moved mean "
        << r["mean_px"].get<double>() << " px, p95 " << r["p95_px"].get<double>() << " px, max "
        << r["max_px"].get<double>() << " px\n";
  }
  return out.str();
}

}  // namespace lsds::noise
