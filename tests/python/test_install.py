"""The package installed by `cmake --install` imports from PREFIX/lib/python3/dist-packages alone,
finds the installed plug-ins, and reads a collection."""
import os
import pathlib
import subprocess
import sys

from helpers import run_lsds

SCRIPT = """
import sys
import lsds
c = lsds.open(sys.argv[1])
print(lsds.__file__)
print(c[0].layer("depth").shape)
print("\\n".join(lsds.plugin_search_dirs()))
"""


def test_import_from_an_installed_prefix(tmp_path):
    build = os.environ["LSDS_BUILD_DIR"]
    cmake = os.environ.get("CMAKE_COMMAND", "cmake")
    prefix = tmp_path / "prefix"
    subprocess.run([cmake, "--install", build, "--prefix", prefix], check=True, capture_output=True)
    site = prefix / "lib" / "python3" / "dist-packages"
    assert list((site / "lsds").glob("_lsds*.so")) and (site / "lsds" / "__init__.py").exists()
    for plugin in ("lsds_image_codecs.so", "lsds_cloud_io.so", "lsds_embree.so", "lsds_mesh_io.so",
                   "lsds_camera_solver.so"):
        assert (prefix / "lib" / "lsds" / plugin).exists(), plugin
    collection = tmp_path / "synth"
    run_lsds("synth", collection, "--count", "1", "--size", "8x6")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LSDS_PLUGIN_DIR")}
    env["PYTHONPATH"] = str(site)
    run = subprocess.run([sys.executable, "-c", SCRIPT, collection], env=env, cwd=tmp_path,
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    module_file, shape, *dirs = run.stdout.splitlines()
    assert pathlib.Path(module_file).is_relative_to(site)
    assert shape == "(6, 8)"
    # The installed plug-ins are found relative to the installed module, before the build tree's.
    assert str(prefix / "lib" / "lsds") in dirs
    assert dirs.index(str(prefix / "lib" / "lsds")) < len(dirs) - 1
