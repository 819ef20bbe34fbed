#!/usr/bin/env bash
# Installs every Debian 12 package that lsds needs to build, test and run its demo.
# Idempotent: when everything is present it only runs dpkg queries and exits in seconds.
#   scripts/install-deps.sh          what the build, the tests and the demo need
#   scripts/install-deps.sh --bench  also the peers the benchmarks compare against (make bench)
set -euo pipefail

packages=(
  build-essential cmake pkg-config ninja-build
  ccache                            # compiles shared between checkouts and runs (CMakeLists.txt)
  libopenexr-dev openexr            # EXR layers (flat + deep) and exrheader/exrinfo for tests
  libopencv-dev                     # images, contours
  libeigen3-dev                     # geometry
  nlohmann-json3-dev                # JSON I/O
  libsimdjson-dev                   # collection.json frames read on demand (libs/collection)
  libvalijson-dev                   # JSON Schema validation
  libcli11-dev                      # command line
  libpcl-dev                        # point clouds
  libceres-dev                      # camera-geometry checks
  libembree-dev libtbb-dev          # reference renderer, parallelism
  libassimp-dev                     # mesh assets
  libgeographiclib-dev              # WGS84 <-> local ENU (geo-referenced scenes)
  libgtest-dev libgmock-dev         # tests
  python3                           # bad-input corpus scripts (tests/validate, tests/hostile)
  python3-numpy                     # export-layers test: numpy.load reads the .npy files
  python3-scipy                     # convert tracking test: TrackEval's Hungarian matching (linear_sum_assignment)
  pybind11-dev python3-pybind11 python3-dev  # the Python module `import lsds` (python/, LSDS_BUILD_PYTHON)
  python3-pytest                    # the Python module's tests (tests/python)
  python3-torch                     # lsds.torch (python/lsds/torch.py) and its tests; ~45 packages, ~1 GB
  python3-opencv python3-openimageio  # tests/python/test_other_readers.py: the default output in OpenCV and OpenImageIO
  clang libclang-rt-14-dev          # the sanitizer build and its fuzz targets (make test-asan)
  clang-tidy                        # make tidy (.clang-tidy)
  clang-format                      # make format-check in CI (.clang-format)
  chromium                          # lsds report end-to-end test: headless screenshot of the page
  slurm-wlm munge                   # scale-out test: a real one-node Slurm (tests/scaleout/slurm_test.sh)
  blender                           # lsds generate --renderer cycles and its test; bench/generate's peer
)
if [ "${1:-}" = "--bench" ]; then
  packages+=(python3-open3d)        # bench/backproject: Open3D create_from_depth_image side by side
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
