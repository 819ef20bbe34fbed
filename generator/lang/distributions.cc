#include "generator/lang/distributions.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

namespace lsds {

double NormalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

double NormalQuantile(double p) {
  if (p <= 0) return -std::numeric_limits<double>::infinity();
  if (p >= 1) return std::numeric_limits<double>::infinity();
  static const double a[] = {-3.969683028665376e+01,
                             2.209460984245205e+02,
                             -2.759285104469687e+02,
                             1.383577518672690e+02,
                             -3.066479806614716e+01,
                             2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01,
                             1.615858368580409e+02,
                             -1.556989798598866e+02,
                             6.680131188771972e+01,
                             -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03,
                             -3.223964580411365e-01,
                             -2.400758277161838e+00,
                             -2.549732539343734e+00,
                             4.374664141464968e+00,
                             2.938163982698783e+00};
  static const double d[] = {
      7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00, 3.754408661907416e+00};
  const double low = 0.02425;
  double x;
  if (p < low) {
    const double q = std::sqrt(-2 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p <= 1 - low) {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  } else {
    const double q = std::sqrt(-2 * std::log(1 - p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  // One Halley step.
  const double e = NormalCdf(x) - p;
  const double u = e * std::sqrt(2 * M_PI) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

double SampleTruncatedNormal(double mean, double sd, double lo, double hi, Rng& rng) {
  if (sd == 0) return std::min(std::max(mean, lo), hi);
  const double p_lo = NormalCdf((lo - mean) / sd), p_hi = NormalCdf((hi - mean) / sd);
  // Inversion within [p_lo, p_hi]; the uniform never hits the ends exactly.
  const double u =
      p_lo + (p_hi - p_lo) * ((static_cast<double>(rng.NextU64() >> 11) + 0.5) * 0x1.0p-53);
  const double x = mean + sd * NormalQuantile(u);
  return std::min(std::max(x, lo), hi);  // far tails: inversion rounding
}

std::optional<double> SampleDistribution(const Node& node, Rng& rng) {
  if (!node->is_object() || node->size() != 1) return std::nullopt;
  const auto [key, value] = node.Members().front();
  const std::string k = CanonicalKey(key);
  if ((k != "normal" && k != "truncatednormal" && k != "gaussian") || !value->is_array())
    return std::nullopt;
  if (value->size() != 2 && value->size() != 4)
    value.Fail("a normal distribution is [mean, sd] or, truncated, [mean, sd, min, max]");
  if (k == "truncatednormal" && value->size() != 4)
    value.Fail("a truncated normal is [mean, sd, min, max]");
  const double mean = ReadNumber(value.Item(0)), sd = ReadNumber(value.Item(1));
  if (!(sd >= 0)) value.Item(1).Fail("the standard deviation must be >= 0");
  double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
  if (value->size() == 4) {
    lo = ReadNumber(value.Item(2));
    hi = ReadNumber(value.Item(3));
    if (!(lo < hi)) value.Fail("a truncated normal needs min < max");
  }
  return SampleTruncatedNormal(mean, sd, lo, hi, rng);
}

std::optional<double> SampleScalarWithin(const Node& node, double lo, double hi, Rng& rng) {
  if (!node.value || !(lo <= hi)) return std::nullopt;
  const OJson& v = *node;
  if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number()) {
    const double a = std::max(lo, ReadNumber(node.Item(0)));
    const double b = std::min(hi, ReadNumber(node.Item(1)));
    if (!(a < b)) return std::nullopt;
    return rng.Uniform(a, b);
  }
  if (!v.is_object() || v.empty()) return std::nullopt;
  if (v.size() == 1) {
    const auto [key, value] = node.Members().front();
    const std::string k = CanonicalKey(key);
    if (k == "normal" || k == "truncatednormal" || k == "gaussian") {
      // Checked by SampleDistribution when the capture was read.
      const double mean = ReadNumber(value.Item(0)), sd = ReadNumber(value.Item(1));
      double a = lo, b = hi;
      if (value->size() == 4) {
        a = std::max(a, ReadNumber(value.Item(2)));
        b = std::min(b, ReadNumber(value.Item(3)));
      }
      // No mass to speak of in [a, b]: leave it to rejection.
      if (!(a < b) || (sd > 0 && NormalCdf((b - mean) / sd) - NormalCdf((a - mean) / sd) < 1e-12))
        return std::nullopt;
      return SampleTruncatedNormal(mean, sd, a, b, rng);
    }
  }
  // A numeric choice {30:0.5, 60:0.5}: its options inside [lo, hi].
  std::vector<double> values, weights;
  for (const auto& [key, child] : node.Members()) {
    char* end = nullptr;
    const double d = std::strtod(key.c_str(), &end);
    if (end == key.c_str() || *end != '\0' || !child->is_number()) return std::nullopt;
    if (d >= lo && d <= hi && ReadNumber(child) > 0) {
      values.push_back(d);
      weights.push_back(ReadNumber(child));
    }
  }
  if (values.empty()) return std::nullopt;
  return values[SampleWeighted(weights, rng)];
}

}  // namespace lsds
