// Statistical tests of the noise models on many draws: the sample standard
// deviation of every field lies in its confidence interval around sigma,
// Gauss-Markov noise has autocorrelation exp(-dt/tau), rotation angles follow
// the Maxwell law of an isotropic 3D Gaussian rotation vector, and a zero sigma
// leaves the truth bit-identical. The seeds are fixed, so the tests are
// deterministic; the intervals are 99.9 % intervals (z = 3.29), not tuned to
// the seeds.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "libs/collection/json_io.h"
#include "libs/util/counter_rng.h"
#include "libs/util/error.h"
#include "perturb/metadata_perturber.h"
#include "perturb/noise_process.h"

namespace lsds::noise {
namespace {

constexpr double kZ = 3.29;  // two-sided 99.9 %
constexpr double kPi = 3.14159265358979323846;

struct Moments {
  double mean = 0, std = 0, kurtosis = 3;
};

Moments Measure(const std::vector<double>& x) {
  Moments m;
  const double n = static_cast<double>(x.size());
  for (double v : x) m.mean += v;
  m.mean /= n;
  double m2 = 0, m4 = 0;
  for (double v : x) {
    const double d = v - m.mean;
    m2 += d * d;
    m4 += d * d * d * d;
  }
  m.std = std::sqrt(m2 / (n - 1));
  m.kurtosis = (m4 / n) / ((m2 / n) * (m2 / n));
  return m;
}

// 99.9 % interval of the sample std of n i.i.d. draws with std sigma and
// kurtosis k: Var(s^2) ~ (k - 1) sigma^4 / n, so sd(s) ~ sigma sqrt((k - 1) /
// n) / 2.
double StdTolerance(double sigma, double kurtosis, size_t n) {
  return kZ * sigma * std::sqrt((kurtosis - 1.0) / static_cast<double>(n)) / 2.0;
}

MetadataFrame NadirTruth(int64_t index, double time) {
  MetadataFrame truth;
  truth.index = index;
  truth.time = time;
  truth.position = {100.0 + index, -50.0, 120.0};
  truth.attitude = {0.0, -90.0, 90.0};
  truth.camera = PinholeCamera::FromHorizontalFov(640, 480, 60);
  return truth;
}

TEST(CounterRng, IsAPureFunctionOfItsCounters) {
  EXPECT_EQ(Uniform01(7, 1, 2, 3), Uniform01(7, 1, 2, 3));
  EXPECT_NE(Uniform01(7, 1, 2, 3), Uniform01(8, 1, 2, 3));
  EXPECT_NE(Uniform01(7, 1, 2, 3), Uniform01(7, 2, 2, 3));
  EXPECT_NE(Uniform01(7, 1, 2, 3), Uniform01(7, 1, 3, 3));
  double lo = 1, hi = 0;
  for (uint64_t k = 0; k < 100000; ++k) {
    const double u = Uniform01(1, 0, k, 0);
    lo = std::min(lo, u);
    hi = std::max(hi, u);
  }
  EXPECT_GT(lo, 0.0);
  EXPECT_LT(hi, 1.0);
  EXPECT_LT(lo, 1e-4);
  EXPECT_GT(hi, 1 - 1e-4);
}

TEST(CounterRng, StandardNormalHasUnitMomentsAndGaussianTails) {
  std::vector<double> x;
  for (uint64_t k = 0; k < 200000; ++k) x.push_back(StandardNormal(42, 3, k));
  const Moments m = Measure(x);
  const double n = static_cast<double>(x.size());
  EXPECT_NEAR(m.mean, 0.0, kZ / std::sqrt(n));
  EXPECT_NEAR(m.std, 1.0, StdTolerance(1.0, 3.0, x.size()));
  EXPECT_NEAR(m.kurtosis, 3.0, kZ * std::sqrt(24.0 / n));
  // P(|x| > 2) = 0.0455 (binomial interval).
  double beyond = 0;
  for (double v : x) beyond += std::abs(v) > 2.0;
  const double p = 0.0455003;
  EXPECT_NEAR(beyond / n, p, kZ * std::sqrt(p * (1 - p) / n));
}

TEST(ScalarProcess, ModelNamesParseAndUnknownNamesAreRefused) {
  EXPECT_EQ(ParseNoiseModel("gaussian"), NoiseModel::kGaussian);
  EXPECT_EQ(ParseNoiseModel("uniform"), NoiseModel::kUniform);
  EXPECT_EQ(ParseNoiseModel("gauss-markov"), NoiseModel::kGaussMarkov);
  try {
    ParseNoiseModel("gausian");
    FAIL() << "no error for an unknown model";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'gaussian'"), std::string::npos) << e.what();
  }
}

// Every field of the perturber, i.i.d. models: sample std of the realized
// errors vs sigma.
class FieldStd : public ::testing::TestWithParam<NoiseModel> {};

TEST_P(FieldStd, SampleStdOfEveryFieldIsWithinItsConfidenceInterval) {
  NoiseSpec spec;
  spec.model = GetParam();
  spec.seed = 2024;
  spec.sigma = {
      1.5, 1.5, 3.0, 0.2, 0.3, 0.5, 0.01, 0.05};  // east north up roll pitch yaw time hfov
  MetadataPerturber perturber(spec, WorldFrame::Make("ENU", "m"));
  const size_t n = 20000;
  std::vector<std::vector<double>> draws(kFieldCount);
  for (size_t k = 0; k < n; ++k) {
    const RealizedError error = perturber.NextError(static_cast<int64_t>(k), 0.1 * k);
    for (int f = 0; f < kFieldCount; ++f) draws[f].push_back(error.value[f]);
  }
  // Kurtosis of the model's law: 3 for the normal, 1.8 for the uniform.
  const double kurtosis = spec.model == NoiseModel::kUniform ? 1.8 : 3.0;
  for (int f = 0; f < kFieldCount; ++f) {
    const Moments m = Measure(draws[f]);
    EXPECT_NEAR(m.std, spec.sigma[f], StdTolerance(spec.sigma[f], kurtosis, n)) << FieldName(f);
    EXPECT_NEAR(m.mean, 0.0, kZ * spec.sigma[f] / std::sqrt(double(n))) << FieldName(f);
    if (spec.model == NoiseModel::kUniform) {
      const double half_width = std::sqrt(3.0) * spec.sigma[f];
      for (double v : draws[f]) ASSERT_LE(std::abs(v), half_width) << FieldName(f);
      EXPECT_NEAR(m.kurtosis, 1.8, 0.05) << FieldName(f);
    }
  }
  // Fields are independent: correlation of east and north within its interval.
  double cross = 0;
  for (size_t k = 0; k < n; ++k) cross += draws[kEast][k] * draws[kNorth][k];
  EXPECT_NEAR(cross / n / (spec.sigma[kEast] * spec.sigma[kNorth]), 0.0, kZ / std::sqrt(double(n)));
}

INSTANTIATE_TEST_SUITE_P(Models,
                         FieldStd,
                         ::testing::Values(NoiseModel::kGaussian, NoiseModel::kUniform));

// Lag-k sample autocorrelation.
double Autocorrelation(const std::vector<double>& x, size_t lag) {
  const Moments m = Measure(x);
  double num = 0, den = 0;
  for (size_t k = 0; k < x.size(); ++k) {
    den += (x[k] - m.mean) * (x[k] - m.mean);
    if (k + lag < x.size()) num += (x[k] - m.mean) * (x[k + lag] - m.mean);
  }
  return num / den;
}

TEST(GaussMarkov, AutocorrelationAtLagDtIsExpMinusDtOverTau) {
  const double tau = 1.0, dt = 0.1, sigma = 2.0;
  const size_t n = 50000;
  ScalarProcess process(NoiseModel::kGaussMarkov, sigma, tau, 99, 0);
  std::vector<double> x;
  for (size_t k = 0; k < n; ++k) x.push_back(process.Next(static_cast<int64_t>(k), dt * k));
  const double phi = std::exp(-dt / tau);
  for (size_t lag : {1, 2, 5, 10, 20}) {
    const double expected = std::pow(phi, double(lag));
    // Bartlett's variance of the lag-k autocorrelation of an AR(1) process.
    const double p2 = phi * phi, p2k = std::pow(phi, 2.0 * lag);
    const double variance = ((1 + p2) * (1 - p2k) / (1 - p2) - 2.0 * lag * p2k) / n;
    EXPECT_NEAR(Autocorrelation(x, lag), expected, kZ * std::sqrt(variance)) << "lag " << lag;
  }
  // Stationary: std sigma. Correlated samples: Var(s^2) ~ 2 sigma^4 (1 + phi^2)
  // / (n (1 - phi^2)).
  const double sd_of_std = sigma * std::sqrt(2.0 * (1 + phi * phi) / (n * (1 - phi * phi))) / 2.0;
  EXPECT_NEAR(Measure(x).std, sigma, kZ * sd_of_std);
}

TEST(GaussMarkov, IrregularStepsUseTheirOwnDt) {
  // Pairs separated by dt = 0.5 tau in a process sampled irregularly:
  // correlation exp(-0.5).
  const double tau = 2.0;
  const size_t pairs = 20000;
  std::vector<double> a, b;
  ScalarProcess process(NoiseModel::kGaussMarkov, 1.0, tau, 5, 0);
  double t = 0;
  for (size_t k = 0; k < pairs; ++k) {
    a.push_back(process.Next(static_cast<int64_t>(2 * k), t));
    t += 0.5 * tau;
    b.push_back(process.Next(static_cast<int64_t>(2 * k + 1), t));
    t += 10 * tau;  // decorrelates the pairs
  }
  double ab = 0, aa = 0, bb = 0;
  for (size_t k = 0; k < pairs; ++k) ab += a[k] * b[k], aa += a[k] * a[k], bb += b[k] * b[k];
  const double r = ab / std::sqrt(aa * bb), rho = std::exp(-0.5);
  EXPECT_NEAR(r, rho, kZ * (1 - rho * rho) / std::sqrt(double(pairs)));
}

TEST(GaussMarkov, RestartsWhenTimeDoesNotIncrease) {
  ScalarProcess a(NoiseModel::kGaussMarkov, 1.0, 1.0, 3, 0);
  ScalarProcess b(NoiseModel::kGaussMarkov, 1.0, 1.0, 3, 0);
  a.Next(0, 0.0);
  a.Next(1, 0.1);
  // A new sequence starting at time 0 again: the same value as a fresh process
  // at that frame.
  EXPECT_EQ(a.Next(2, 0.0), b.Next(2, 0.0));
}

// Maxwell CDF: the norm of a 3D vector of i.i.d. N(0, s^2) components.
double MaxwellCdf(double x, double s) {
  return std::erf(x / (s * std::sqrt(2.0))) -
         std::sqrt(2.0 / kPi) * (x / s) * std::exp(-x * x / (2 * s * s));
}

TEST(RotationNoise, AnglesFollowTheMaxwellLawAndAreTheTrueAngularDistance) {
  NoiseSpec spec;
  spec.seed = 77;
  const double s = 0.5;  // degrees, every axis
  spec.sigma[kRoll] = spec.sigma[kPitch] = spec.sigma[kYaw] = s;
  MetadataPerturber perturber(spec, WorldFrame::Make("ENU", "m"));
  const size_t n = 5000;
  std::vector<double> angles;
  for (size_t k = 0; k < n; ++k) {
    MetadataFrame truth = NadirTruth(static_cast<int64_t>(k), 0.1 * k);
    truth.attitude = {3.0 * std::sin(0.01 * k), -90.0 + 60.0 * (k % 7) / 7.0, -170.0 + 0.07 * k};
    const MetadataFrame measured = perturber.Perturb(truth);
    const double angle = measured.error["rotation_deg"].get<double>();
    angles.push_back(angle);
    // The recorded angle is the angle between the true and the measured
    // attitudes.
    const double actual =
        NedFromBody(truth.attitude).angularDistance(NedFromBody(measured.attitude));
    ASSERT_NEAR(actual * 180.0 / kPi, angle, 1e-6) << "frame " << k;
  }
  // Kolmogorov-Smirnov against Maxwell(s): D < 1.95 / sqrt(n) at the 0.1 %
  // level.
  std::sort(angles.begin(), angles.end());
  double d = 0;
  for (size_t k = 0; k < n; ++k) {
    const double cdf = MaxwellCdf(angles[k], s);
    d = std::max({d, cdf - double(k) / n, double(k + 1) / n - cdf});
  }
  EXPECT_LT(d, 1.95 / std::sqrt(double(n)));
  // Mean 2 s sqrt(2 / pi), E[angle^2] = 3 s^2.
  double sum = 0, sum2 = 0;
  for (double a : angles) sum += a, sum2 += a * a;
  const double mean = 2 * s * std::sqrt(2 / kPi);
  const double sd = s * std::sqrt(3 - 8 / kPi);
  EXPECT_NEAR(sum / n, mean, kZ * sd / std::sqrt(double(n)));
  EXPECT_NEAR(sum2 / n, 3 * s * s, kZ * s * s * std::sqrt(6.0 / n));
}

TEST(RotationNoise, AxesAreHeadingLevelForwardRightDown) {
  const Attitude level{0.0, 0.0, 30.0};
  // Roll error about forward: roll changes, pitch and yaw do not.
  Attitude a = RotateAttitude(level, {1.0, 0.0, 0.0});
  EXPECT_NEAR(a.roll_deg, 1.0, 1e-9);
  EXPECT_NEAR(a.pitch_deg, 0.0, 1e-9);
  EXPECT_NEAR(a.yaw_deg, 30.0, 1e-9);
  a = RotateAttitude(level, {0.0, 1.0, 0.0});
  EXPECT_NEAR(a.pitch_deg, 1.0, 1e-9);
  EXPECT_NEAR(a.yaw_deg, 30.0, 1e-9);
  a = RotateAttitude(level, {0.0, 0.0, 1.0});
  EXPECT_NEAR(a.yaw_deg, 31.0, 1e-9);
  EXPECT_NEAR(a.pitch_deg, 0.0, 1e-9);
  // Zero rotation: the attitude is returned as it is, bit for bit.
  const Attitude odd{0.1 + 0.2, -89.999999999, 359.0};
  const Attitude same = RotateAttitude(odd, Eigen::Vector3d::Zero());
  EXPECT_EQ(same.roll_deg, odd.roll_deg);
  EXPECT_EQ(same.pitch_deg, odd.pitch_deg);
  EXPECT_EQ(same.yaw_deg, odd.yaw_deg);
}

TEST(Perturber, ZeroSigmaLeavesTheTruthBitIdentical) {
  for (NoiseModel model : {NoiseModel::kGaussian, NoiseModel::kUniform, NoiseModel::kGaussMarkov}) {
    NoiseSpec spec;
    spec.model = model;
    spec.tau = model == NoiseModel::kGaussMarkov ? 1.0 : 0.0;
    MetadataPerturber perturber(spec, WorldFrame::Make("ENU", "m"));
    for (int k = 0; k < 100; ++k) {
      MetadataFrame truth = NadirTruth(k, 0.1 * k + 1e-7);
      truth.position = {-0.0, 1.0 / 3.0, 1e-300};
      truth.attitude = {0.1 + 0.2, -89.99, 1.0 / 7.0};
      const MetadataFrame measured = perturber.Perturb(truth);
      EXPECT_EQ(MetadataFrameToJson(measured).dump(),
                MetadataFrameToJson([&] {
                  MetadataFrame expected = truth;
                  expected.error = measured.error;
                  return expected;
                }())
                    .dump());
      EXPECT_TRUE(std::signbit(measured.position.x()));
      EXPECT_EQ(measured.error["rotation_deg"].get<double>(), 0.0);
      EXPECT_EQ(measured.error["position"], nlohmann::json::array({0.0, 0.0, 0.0}));
    }
  }
}

TEST(Perturber, BiasIsAddedExactlyAndMappedIntoTheDeclaredFrame) {
  NoiseSpec spec;
  spec.bias[kEast] = 1.0;
  spec.bias[kNorth] = 2.0;
  spec.bias[kUp] = 3.0;
  spec.bias[kTime] = 0.25;
  const MetadataFrame truth = NadirTruth(4, 0.4);
  {
    MetadataPerturber enu(spec, WorldFrame::Make("ENU", "m"));
    const MetadataFrame m = enu.Perturb(truth);
    EXPECT_EQ(m.position - truth.position, Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(m.time, truth.time + 0.25);
  }
  {
    // NED: north, east, down.
    MetadataPerturber ned(spec, WorldFrame::Make("NED", "m"));
    const MetadataFrame m = ned.Perturb(truth);
    EXPECT_EQ(m.position - truth.position, Eigen::Vector3d(2, 1, -3));
    EXPECT_EQ(m.error["position"], nlohmann::json::array({2.0, 1.0, -3.0}));
    EXPECT_EQ(m.error["position_enu_m"], nlohmann::json::array({1.0, 2.0, 3.0}));
  }
  {
    // Unreal: x north, y east, z up, centimetres.
    MetadataPerturber unreal(spec, WorldFrame::Make("unreal", "cm"));
    const MetadataFrame m = unreal.Perturb(truth);
    EXPECT_NEAR((m.position - truth.position - Eigen::Vector3d(200, 100, 300)).norm(), 0, 1e-9);
  }
}

TEST(Perturber, FieldOfViewNoiseKeepsPrincipalPointAndAspect) {
  NoiseSpec spec;
  spec.bias[kHfov] = 2.0;
  MetadataPerturber perturber(spec, WorldFrame::Make("ENU", "m"));
  MetadataFrame truth = NadirTruth(0, 0);
  truth.camera.fy = truth.camera.fx * 1.1;
  const MetadataFrame m = perturber.Perturb(truth);
  EXPECT_NEAR(m.camera.HorizontalFovDeg(), 62.0, 1e-9);
  EXPECT_NEAR(m.camera.fy / m.camera.fx, 1.1, 1e-12);
  EXPECT_EQ(m.camera.cx, truth.camera.cx);
  EXPECT_EQ(m.camera.cy, truth.camera.cy);
  spec.bias[kHfov] = 150.0;
  MetadataPerturber too_wide(spec, WorldFrame::Make("ENU", "m"));
  EXPECT_THROW(too_wide.Perturb(truth), Error);
}

TEST(Perturber, DrawsDependOnlyOnSeedFieldAndFrame) {
  NoiseSpec spec;
  spec.seed = 11;
  spec.sigma.fill(1.0);
  MetadataPerturber all(spec, WorldFrame::Make("ENU", "m"));
  MetadataPerturber subset(spec, WorldFrame::Make("ENU", "m"));
  std::vector<RealizedError> full;
  for (int k = 0; k < 10; ++k) full.push_back(all.NextError(k, 0.1 * k));
  // Frames 3 and 7 alone get the same errors as in the full run (i.i.d.
  // models).
  EXPECT_EQ(subset.NextError(7, 0.7).value, full[7].value);
  EXPECT_EQ(subset.NextError(3, 0.3).value, full[3].value);
  spec.seed = 12;
  MetadataPerturber other(spec, WorldFrame::Make("ENU", "m"));
  EXPECT_NE(other.NextError(3, 0.3).value, full[3].value);
}

TEST(NoiseSpec, RefusesNegativeSigmaAndMisplacedTau) {
  NoiseSpec spec;
  spec.sigma[kUp] = -1;
  EXPECT_THROW(spec.Validate(), Error);
  spec.sigma[kUp] = std::nan("");
  EXPECT_THROW(spec.Validate(), Error);
  spec.sigma[kUp] = 1;
  spec.Validate();
  spec.tau = 1;
  EXPECT_THROW(spec.Validate(), Error);  // tau without gauss-markov
  spec.model = NoiseModel::kGaussMarkov;
  spec.Validate();
  spec.tau = 0;
  EXPECT_THROW(spec.Validate(), Error);  // gauss-markov without tau
}

}  // namespace
}  // namespace lsds::noise
