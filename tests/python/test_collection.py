"""lsds.open: the collection as a sequence of frames, its tables and every frame's truth equal to
collection.json; cameras, metadata; threads and fork."""
import subprocess
import sys
import threading

import numpy as np
import pytest

import lsds
from helpers import collection_json, same_array


def test_tables_equal_collection_json(demo_residual):
    c = lsds.open(demo_residual)
    doc = collection_json(demo_residual)
    assert c.classes == doc["classes"]
    assert c.layers == doc["layers"]
    assert c.provenance == doc["provenance"]
    assert c.conventions == doc["conventions"]
    assert c.format_version == doc["format_version"]
    assert c.rig is None
    assert c.path == str(demo_residual)
    assert "frames" not in c.header and c.header["frame_count"] == len(c) == len(doc["frames"])


def test_frames_equal_collection_json(demo_residual, rig, synth):
    for collection in (demo_residual, rig, synth):
        c = lsds.open(collection)
        doc = collection_json(collection)
        for frame, expected in zip(c, doc["frames"]):
            assert frame.objects == expected["objects"]
            assert frame.json == expected
            assert frame.index == expected["index"] and frame.time == expected["time"]
            assert frame.files == expected["files"]
            assert frame.rig_camera == expected.get("rig_camera")
            assert frame.step == expected.get("step")
        assert any(frame.objects for frame in c)


def test_sequence_protocol(synth):
    c = lsds.open(synth)
    assert len(c) == 3 and len(c.frames) == 3
    assert [f.index for f in c] == [0, 1, 2]
    assert c[-1].index == 2 and c.frames[0].index == 0
    assert [f.index for f in c[1:]] == [1, 2] and [f.index for f in c[::2]] == [0, 2]
    assert c.frame(1).index == 1
    with pytest.raises(IndexError):
        c[3]
    with pytest.raises(KeyError):
        c.frame(7)


def test_camera(demo_residual):
    c = lsds.open(demo_residual)
    for frame, expected in zip(c, collection_json(demo_residual)["frames"]):
        cam = expected["camera"]
        K = frame.camera.K
        assert K.shape == (3, 3) and K.dtype == np.float64
        assert (K == [[cam["fx"], 0, cam["cx"]], [0, cam["fy"], cam["cy"]], [0, 0, 1]]).all()
        T = frame.camera.cam_from_world
        assert T.shape == (4, 4)
        assert (T[:3, :3] == cam["cam_from_world"]["rotation"]).all()
        assert (T[:3, 3] == cam["cam_from_world"]["translation"]).all()
        assert (T[3] == [0, 0, 0, 1]).all()
        assert np.allclose(frame.camera.world_from_cam @ T, np.eye(4), atol=1e-9)
        assert (frame.camera.width, frame.camera.height) == (24, 16)
        assert frame.camera.json == cam


def test_projection_of_depth_matches_worldposition(synth):
    """camera.K and cam_from_world put the world position of a pixel back onto its centre."""
    frame = lsds.open(synth)[0]
    world = frame.layer("worldposition").astype(np.float64)
    y, x = 12, 17
    p = frame.camera.cam_from_world @ np.append(world[y, x], 1.0)
    u, v, w = frame.camera.K @ p[:3]
    assert abs(u / w - (x + 0.5)) < 1e-3 and abs(v / w - (y + 0.5)) < 1e-3


def test_metadata(synth):
    c = lsds.open(synth)
    for frame in c:
        assert frame.metadata is not None and frame.metadata["index"] == frame.index


def test_threads_decode_the_same(demo_residual):
    c = lsds.open(demo_residual)
    expected = [f.layer("worldposition") for f in c]
    results = [None] * 8

    def work(k):
        results[k] = c[k % len(c)].layer("worldposition")

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(same_array(r, expected[k % len(c)]) for k, r in enumerate(results))
    # A collection opened with several threads decodes the same values.
    assert same_array(lsds.open(demo_residual, threads=2)[0].layer("motion"), c[0].layer("motion"))


FORK_SCRIPT = """
import os, sys
import lsds
c = lsds.open(sys.argv[1])
before = c[0].layer("worldposition")
c[1].bundle()
assert len(os.listdir("/proc/self/task")) == 1, "a thread was started"
pid = os.fork()
if pid == 0:  # the child decodes too
    os._exit(0 if c[0].layer("worldposition").tobytes() == before.tobytes() else 1)
_, status = os.waitpid(pid, 0)
assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0, status
print("ok")
"""


def test_decoding_starts_no_thread_and_survives_fork(demo_residual):
    """In a fresh interpreter: decoding with threads=1 starts no TBB worker; a forked child
    (a DataLoader worker) decodes the same."""
    run = subprocess.run([sys.executable, "-c", FORK_SCRIPT, str(demo_residual)],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and run.stdout.strip() == "ok", run.stderr
