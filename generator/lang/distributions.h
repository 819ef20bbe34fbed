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

}  // namespace lsds
