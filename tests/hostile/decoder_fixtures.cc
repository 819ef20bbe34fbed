// Writes one valid source of an importer into a folder, from the fixtures of
// tests/import (analytic lsds scenes in each simulator's layout), for the
// decoder corpus (decoder_corpus.py) to break one file of:
//   decoder_fixtures FORMAT FOLDER     FORMAT: ue-mrq airsim bop kubric replicator solo
// Prints the source folder to give to `lsds import FORMAT`.
#include <filesystem>
#include <iostream>
#include <string>

#include "libs/synth/synthetic_collection.h"
#include "tests/import/airsim_fixture.h"
#include "tests/import/bop_fixture.h"
#include "tests/import/kubric_fixture.h"
#include "tests/import/mrq_fixture.h"
#include "tests/import/replicator_fixture.h"
#include "tests/import/solo_fixture.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: decoder_fixtures ue-mrq|airsim|bop|kubric|replicator|solo FOLDER\n";
    return 2;
  }
  const std::string format = argv[1];
  const fs::path folder = argv[2];
  // Two small frames: enough for every reader, quick to write and import.
  lsds::synth::Spec spec = lsds::synth::DefaultSpec();
  spec.samples_per_axis = 1;
  spec.cam_from_world.resize(2);
  fs::path source = folder;
  if (format == "ue-mrq") {
    lsds::testing::WriteMrqFixture(folder, spec);
  } else if (format == "airsim") {
    lsds::testing::WriteAirSimFixture(folder, spec);
  } else if (format == "bop") {
    source = lsds::testing::WriteBopFixture(folder, spec);
  } else if (format == "kubric") {
    spec.depth_kind = lsds::DepthKind::kPerspective;  // Kubric's depth: ray distance
    lsds::testing::WriteKubricFixture(folder, spec);
  } else if (format == "replicator") {
    lsds::testing::WriteReplicatorFixture(folder, spec);
  } else if (format == "solo") {
    lsds::testing::WriteSoloFixture(folder, spec, 1);
  } else {
    std::cerr << "unknown format " << format << "\n";
    return 2;
  }
  std::cout << source.string() << "\n";
  return 0;
}
