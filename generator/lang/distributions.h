// Numeric distributions beyond the uniform interval (docs/languages.md,
// "Values"): `{normal:[mean, sd]}` and the truncated normal
// `{normal:[mean, sd, min, max]}` (also spelt `truncated_normal`). Drawn from
// the planner's Rng by inversion, so one uniform per draw and no
// implementation-defined std:: distribution.
#pragma once

#include <optional>

#include "generator/lang/random.h"
#include "generator/lang/values.h"

namespace lsds {

// Standard normal CDF and its inverse (Acklam's rational approximation refined
// by one Halley step: |error| < 1e-12 on (0, 1)).
double NormalCdf(double x);
double NormalQuantile(double p);

// A draw from N(mean, sd) truncated to [lo, hi] (infinite bounds: untruncated).
double SampleTruncatedNormal(double mean, double sd, double lo, double hi, Rng& rng);

// When `node` is a distribution object ({normal:[...]}), its draw; nullopt for
// every other value (then it is a choice or something else).
std::optional<double> SampleDistribution(const Node& node, Rng& rng);

// Importance sampling of a quota bin (docs/languages.md, "Requirements and
// quotas"): a draw of the scalar `node` conditioned on lying in [lo, hi] -
// an interval's uniform on its intersection with [lo, hi], a normal truncated
// to it, a numeric choice among its options inside it (weights renormalised).
// nullopt when the value cannot be conditioned (a fixed number, another form)
// or has no probability in [lo, hi]; then the caller draws as usual.
std::optional<double> SampleScalarWithin(const Node& node, double lo, double hi, Rng& rng);

}  // namespace lsds
