"""Helpers of the Python module's tests (conftest.py makes the collections)."""
import json
import os
import pathlib
import subprocess

LSDS = os.environ.get("LSDS_BINARY", "lsds")


def run_lsds(*args, check=True):
    """Runs the CLI quietly; returns the completed process."""
    return subprocess.run([LSDS, *map(str, args), "-q"], check=check, capture_output=True, text=True)


def exported(collection, workdir):
    """`lsds export-layers --to npy` of every flat layer of `collection` (made once)."""
    out = pathlib.Path(workdir) / (pathlib.Path(collection).name + "_npy")
    if not out.exists():
        run_lsds("export-layers", collection, "--to", "npy", "-o", out)
    return out


def collection_json(collection):
    with open(pathlib.Path(collection) / "collection.json", encoding="utf-8") as f:
        return json.load(f)


def same_array(a, b):
    """Bit for bit: dtype, shape and bytes (NaN and inf included)."""
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
