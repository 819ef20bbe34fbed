// A built-in demonstration plan: hilly grassy terrain with barrels, tires,
// jerrycans, rocks, bushes, people and cubes, seen by a camera flying a
// straight line at 40 m looking 30 degrees forward of nadir. Used by `lsds
// generate --demo`, the benchmark and the end-to-end tests, so that none of
// them needs the LSCENE/LCAP parser.
#pragma once

#include <cstdint>

#include "generator/plan/plan.h"

namespace lsds::gen {

struct DemoOptions {
  int frames = 24;
  int width = 512;
  int height = 512;
  uint64_t seed = 0;
  int objects = 60;
};

Plan MakeDemoPlan(const DemoOptions& options);

}  // namespace lsds::gen
