"""Collections for the Python module's tests, made once per session with the lsds CLI.

ctest sets LSDS_BINARY (the lsds binary), PYTHONPATH (build/<preset>/python, the package in the
build tree) and LSDS_BUILD_DIR (tests/python/CMakeLists.txt).
"""
import pathlib
import shutil

import pytest

from helpers import run_lsds

# A 2 m cube on flat ground under a stereo pair plus a smaller third camera: a rig collection of
# 2 time steps x 3 cameras (tests/generator/rig_test.cc's rig, smaller).
RIG_SCENE = """LSCENE = ONE(W) ONE(CUBE)
W = terrain{size:[60,60]}
CUBE = object{class:cube,extent:[2,2,2],position:{ON:W,within:[[-0.01,-0.01,-10],[0.01,0.01,10]]}}
"""
RIG_CAPTURE = """LCAP = ONE(CO) ONE(P) ONE(CL)
CO = camera{csettings:{fov:60,res:[24,18],fps:10},targets:[CUBE],
  rig:{left:{position:[-0.25,0,0]},right:{position:[0.25,0,0]},
       nir:{position:[0,0.1,0],csettings:{fov:40,res:[12,9]}}}}
P = path{waypoints:{points:[[-0.25,0,20],[0.25,0,20]],speed:5}}
CL = collection{CO:{move:[P]}}
"""

# The tiny demo render of the CLI tests: in the default layouts (float worldposition and motion,
# residual bundle), --compact (every layer residual) and the plainest (float, full bundle).
DEMO = ["generate", "--demo", "--demo-frames", "2", "--demo-size", "24x16", "--spp", "4", "--seed", "3"]
COMPACT_LAYOUTS = ["--compact"]
FLOAT_LAYOUTS = ["--bundle-layout", "full"]


@pytest.fixture(scope="session")
def workdir(tmp_path_factory):
    return tmp_path_factory.mktemp("lsds")


def _made(workdir, name, *args):
    out = workdir / name
    if not out.exists():
        run_lsds(*args, "-o", out)
    return out


@pytest.fixture(scope="session")
def synth(workdir):
    out = workdir / "synth"
    run_lsds("synth", out, "--count", "3", "--size", "40x30")
    return out


@pytest.fixture(scope="session")
def demo_residual(workdir):
    return _made(workdir, "demo_residual", *DEMO, *COMPACT_LAYOUTS)


@pytest.fixture(scope="session")
def demo_default(workdir):
    return _made(workdir, "demo_default", *DEMO)


@pytest.fixture(scope="session")
def demo_float(workdir):
    return _made(workdir, "demo_float", *DEMO, *FLOAT_LAYOUTS)


@pytest.fixture(scope="session")
def demo_compact(workdir):
    return _made(workdir, "demo_compact", *DEMO, "--bundle-layout", "compact")


@pytest.fixture(scope="session")
def rig(workdir):
    scene = workdir / "cube.lscene"
    capture = workdir / "stereo.lcap"
    scene.write_text(RIG_SCENE)
    capture.write_text(RIG_CAPTURE)
    return _made(workdir, "rig", "generate", scene, capture, "--spp", "1")


@pytest.fixture
def copy_of(tmp_path):
    """copy_of(collection) -> a copy to corrupt."""
    def make(collection):
        target = tmp_path / (pathlib.Path(collection).name + "_copy")
        shutil.copytree(collection, target)
        return target
    return make
