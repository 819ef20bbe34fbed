// write_import_fixture FORMAT DIR [--nan-depth]: writes the import fixture of
// FORMAT (the same writers as the import tests) for a small two-frame scene
// into DIR and prints the source folder to give `lsds import` (for bop, DIR's
// scene folder). --nan-depth (solo, kubric) then puts a NaN into pixel (3, 2)
// of frame 0's depth image, which a script cannot easily do to an EXR or TIFF.
// The hostile import corpus (tests/hostile/import_corpus.py) mutates these.
#include <iostream>
#include <limits>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "libs/exr/flat_image.h"

#include "synth/synthetic_collection.h"
#include "tests/import/airsim_fixture.h"
#include "tests/import/bop_fixture.h"
#include "tests/import/kubric_fixture.h"
#include "tests/import/mrq_fixture.h"
#include "tests/import/replicator_fixture.h"
#include "tests/import/solo_fixture.h"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  using namespace lsds::testing;  // NOLINT(google-build-using-namespace)
  const bool nan_depth = argc == 4 && std::string(argv[3]) == "--nan-depth";
  if (argc != 3 && !nan_depth) {
    std::cerr << "usage: write_import_fixture ue-mrq|airsim|bop|kubric|replicator|solo DIR "
                 "[--nan-depth]\n";
    return 2;
  }
  constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
  const std::string format = argv[1];
  const fs::path dir = argv[2];
  lsds::synth::Spec spec = lsds::synth::DefaultSpec();
  spec.samples_per_axis = 1;  // one sample per pixel: ids as the sources write them
  spec.cam_from_world.resize(2);
  fs::path source = dir;
  if (format == "ue-mrq") {
    WriteMrqFixture(dir, spec);
  } else if (format == "airsim") {
    WriteAirSimFixture(dir, spec);
  } else if (format == "bop") {
    source = WriteBopFixture(dir, spec);
  } else if (format == "kubric") {
    spec.depth_kind = lsds::DepthKind::kPerspective;
    WriteKubricFixture(dir, spec);
    if (nan_depth) {
      const std::string tiff = (dir / "depth_00000.tiff").string();
      cv::Mat depth = cv::imread(tiff, cv::IMREAD_UNCHANGED);
      depth.at<float>(2, 3) = kNan;
      cv::imwrite(tiff, depth);
    }
  } else if (format == "replicator") {
    WriteReplicatorFixture(dir, spec);
  } else if (format == "solo") {
    WriteSoloFixture(dir, spec, 1);
    if (nan_depth) {
      const fs::path exr = dir / "sequence.0" / "step0.camera.Depth.exr";
      lsds::exr::FlatImage depth = lsds::exr::ReadFlatExr(exr);
      depth.Get("R").floats[depth.Index(3, 2)] = kNan;
      lsds::exr::WriteFlatExr(exr, depth);
    }
  } else {
    std::cerr << "unknown format '" << format << "'\n";
    return 2;
  }
  std::cout << source.string() << "\n";
  return 0;
}
