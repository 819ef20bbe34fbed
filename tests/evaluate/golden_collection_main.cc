// evaluate_golden_collection OUT: writes the collection of the evaluate goldens
// (golden_collection.h) for make_goldens.py.
#include <cstdio>
#include <exception>

#include "tests/evaluate/golden_collection.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: evaluate_golden_collection OUT\n");
    return 2;
  }
  try {
    lsds::synth::WriteCollection(argv[1], lsds::testing::EvaluateGoldenSpec());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
