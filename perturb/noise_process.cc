#include "perturb/noise_process.h"

#include <cmath>

#include "libs/util/counter_rng.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::noise {

const char* NoiseModelName(NoiseModel model) {
  switch (model) {
    case NoiseModel::kGaussian:
      return "gaussian";
    case NoiseModel::kUniform:
      return "uniform";
    case NoiseModel::kGaussMarkov:
      return "gauss-markov";
  }
  return "gaussian";
}

const std::vector<std::string>& NoiseModelNames() {
  static const std::vector<std::string> names = {"gaussian", "uniform", "gauss-markov"};
  return names;
}

NoiseModel ParseNoiseModel(const std::string& name) {
  if (name == "gaussian") return NoiseModel::kGaussian;
  if (name == "uniform") return NoiseModel::kUniform;
  if (name == "gauss-markov") return NoiseModel::kGaussMarkov;
  throw Error("unknown noise model '" + name + "'" + DidYouMean(name, NoiseModelNames()) +
              "; expected one of: " + Join(NoiseModelNames(), ", "));
}

ScalarProcess::ScalarProcess(
    NoiseModel model, double sigma, double tau, uint64_t seed, uint64_t field)
    : model_(model), sigma_(sigma), tau_(tau), seed_(seed), field_(field) {}

double ScalarProcess::Next(int64_t frame_index, double time) {
  if (sigma_ == 0.0) return 0.0;
  const uint64_t frame = static_cast<uint64_t>(frame_index);
  switch (model_) {
    case NoiseModel::kGaussian:
      return sigma_ * StandardNormal(seed_, field_, frame);
    case NoiseModel::kUniform:
      return sigma_ * std::sqrt(3.0) * (2.0 * Uniform01(seed_, field_, frame, 0) - 1.0);
    case NoiseModel::kGaussMarkov: {
      const double n = StandardNormal(seed_, field_, frame);
      const double dt = time - previous_time_;
      if (!started_ || !(dt > 0.0) || !std::isfinite(dt)) {
        state_ = sigma_ * n;
      } else {
        const double phi = std::exp(-dt / tau_);
        state_ = phi * state_ + sigma_ * std::sqrt(1.0 - phi * phi) * n;
      }
      started_ = true;
      previous_time_ = time;
      return state_;
    }
  }
  return 0.0;
}

}  // namespace lsds::noise
