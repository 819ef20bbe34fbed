// Generating a scene and capture through the CLI the way a user does, then the gate: for the
// generator tests that check a rendered collection.
#pragma once

#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/test_util.h"

namespace lsds::testing {

// Writes `scene` and `capture` into `dir`, generates them into dir/out (--spp 1) and validates
// the result with --fail-on warning (test failures otherwise); the collection.json.
inline nlohmann::json GenerateValidated(const TempDir& dir,
                                        const std::string& scene,
                                        const std::string& capture) {
  std::ofstream(dir / "s.lscene") << scene;
  std::ofstream(dir / "c.lcap") << capture;
  const std::string out = (dir / "out").string();
  const auto generated =
      RunCommandLine(LsdsBinary() + " generate " + (dir / "s.lscene").string() + " " +
                     (dir / "c.lcap").string() + " -o " + out + " --spp 1 -q");
  EXPECT_EQ(generated.exit_code, 0) << generated.output;
  const auto validated = RunCommandLine(LsdsBinary() + " validate " + out + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
  std::ifstream in(dir / "out" / "collection.json");
  return in ? nlohmann::json::parse(in) : nlohmann::json();
}

}  // namespace lsds::testing
