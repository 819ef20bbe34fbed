// Scalar noise processes: i.i.d. Gaussian, i.i.d. uniform, and first-order
// Gauss-Markov (the standard model of GNSS/INS drift). Each has standard
// deviation `sigma`; draws are deterministic per (seed, field, frame index)
// (counter_rng.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lsds::noise {

enum class NoiseModel { kGaussian, kUniform, kGaussMarkov };

const char* NoiseModelName(NoiseModel model);  // "gaussian" | "uniform" | "gauss-markov"
const std::vector<std::string>& NoiseModelNames();
// Throws lsds::Error for an unknown name, with a did-you-mean suggestion.
NoiseModel ParseNoiseModel(const std::string& name);

// One field's noise over a sequence of frames, visited in time order.
//  gaussian:     e_k = sigma * n_k
//  uniform:      e_k = sigma * sqrt(3) * (2 u_k - 1)         (uniform on
//  [-sqrt(3) sigma, sqrt(3) sigma]) gauss-markov: e_0 = sigma * n_0,
//                e_k = phi e_{k-1} + sigma sqrt(1 - phi^2) n_k, phi = exp(-dt_k
//                / tau) (stationary: std sigma at every frame, autocorrelation
//                exp(-dt / tau)); the process restarts from its stationary law
//                when time does not increase (a new sequence).
// sigma == 0 gives exactly 0 without drawing, so a zero sigma leaves the truth
// bit-identical.
class ScalarProcess {
 public:
  ScalarProcess(NoiseModel model, double sigma, double tau, uint64_t seed, uint64_t field);
  // The noise at the frame with `frame_index` and time `time` (seconds).
  double Next(int64_t frame_index, double time);
  void Reset() { started_ = false; }

 private:
  NoiseModel model_;
  double sigma_;
  double tau_;
  uint64_t seed_;
  uint64_t field_;
  bool started_ = false;
  double previous_time_ = 0;
  double state_ = 0;
};

}  // namespace lsds::noise
