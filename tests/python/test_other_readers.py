"""The default generator output read WITHOUT lsds: OpenCV (`cv2.imread(path, IMREAD_UNCHANGED)`)
and OpenImageIO get the true float world positions and motion, equal bit for bit to what lsds's
own reader decodes and, on the flat ground and the cube top of the rig scene, to the ray-plane
intersections its cameras predict. And `--compact` (the residual layouts) still decodes bit for bit
to the same values. Debian's python3-opencv and python3-openimageio (scripts/install-deps.sh)."""
import numpy as np
import pytest

import lsds
from conftest import COMPACT_LAYOUTS, DEMO
from helpers import collection_json, run_lsds, same_array

cv2 = pytest.importorskip("cv2")
oiio = pytest.importorskip("OpenImageIO")


def oiio_read(path):
    """(channel names, pixel types, float32 array H x W x C) as OpenImageIO reads the file."""
    image = oiio.ImageInput.open(str(path))
    assert image is not None, oiio.geterror()
    spec = image.spec()
    pixels = image.read_image(oiio.FLOAT)
    image.close()
    types = [str(spec.channelformat(c)) for c in range(spec.nchannels)]
    return list(spec.channelnames), types, pixels


def files_of(collection, layer):
    root = collection
    return [root / frame["files"][layer] for frame in collection_json(collection)["frames"]]


def test_default_layers_are_plain_floats_in_opencv_and_openimageio(demo_default):
    c = lsds.open(demo_default)
    for layer, channels in (("worldposition", ["X", "Y", "Z"]), ("motion", ["X", "Y"])):
        for frame, path in zip(c, files_of(demo_default, layer)):
            truth = frame.layer(layer)  # lsds's reader: H x W x C float32
            names, types, pixels = oiio_read(path)
            assert names == channels and types == ["float"] * len(channels), (path, names, types)
            assert same_array(pixels.astype(np.float32), truth), path
            # OpenCV maps channels named R, G, B or Y only: X, Y, Z and X, Y come back as one
            # channel, Y (docs/export-layers.md); that channel is the true float Y.
            read = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
            assert read is not None, path
            assert read.dtype == np.float32 and read.shape == truth.shape[:2], (path, read.shape)
            assert same_array(read, np.ascontiguousarray(truth[:, :, 1])), path


def plane_hits(frame, height):
    """The world points where each pixel-centre ray of `frame` meets the plane z = height."""
    K = np.asarray(frame.camera.K, dtype=np.float64)
    cam_from_world = np.asarray(frame.camera.cam_from_world, dtype=np.float64)
    rotation, translation = cam_from_world[:3, :3], cam_from_world[:3, 3]
    centre = -rotation.T @ translation
    h, w = frame.layer("depth").shape[:2]
    j, i = np.mgrid[0:h, 0:w]
    rays_in_cam = np.stack([(i + 0.5 - K[0, 2]) / K[0, 0], (j + 0.5 - K[1, 2]) / K[1, 1],
                            np.ones((h, w))], axis=-1)
    rays = rays_in_cam @ rotation  # R^T r, row by row
    s = (height - centre[2]) / rays[..., 2]
    return centre + s[..., None] * rays


def test_openimageio_world_positions_are_the_scene_geometry(rig):
    """Rig scene: a 2 m cube on flat ground (z = 0) seen from 20 m. Every pixel's X, Y, Z as
    OpenImageIO reads it is where the pixel's ray meets the ground or the cube's top (z = 2)."""
    c = lsds.open(rig)
    assert c.layers[[l["name"] for l in c.layers].index("worldposition")].get("layout", "float") == "float"
    on_planes = total = 0
    for frame, path in zip(c, files_of(rig, "worldposition")):
        _, _, xyz = oiio_read(path)
        total += xyz.shape[0] * xyz.shape[1]
        for height in (0.0, 2.0):
            on_plane = np.abs(xyz[..., 2] - height) < 1e-4
            hits = plane_hits(frame, height)
            assert np.abs(xyz[on_plane][:, :2] - hits[on_plane][:, :2]).max() < 1e-3, (path, height)
            on_planes += int(on_plane.sum())
    # The cube's sides are the rest (a few pixels at its silhouette).
    assert on_planes >= 0.9 * total, (on_planes, total)


def test_compact_round_trips_bit_for_bit(workdir, demo_default):
    """--compact writes UINT residuals (not readable as floats elsewhere) that lsds decodes to
    exactly the default's float X, Y, Z and X, Y (NaN and inf included): the residual layouts are
    lossless by construction (docs/format.md, "Worldposition layouts")."""
    compact = workdir / "demo_compact_same_seed"
    if not compact.exists():
        run_lsds(*DEMO, *COMPACT_LAYOUTS, "-o", compact)
    plain, packed = lsds.open(demo_default), lsds.open(compact)
    for layer, stored in (("worldposition", ["dX", "dY", "dZ"]), ("motion", ["dX", "dY"])):
        names, types, _ = oiio_read(files_of(compact, layer)[1])
        assert names == stored and types == ["uint"] * len(stored), (names, types)
        for a, b in zip(plain, packed):
            assert same_array(a.layer(layer), b.layer(layer)), (layer, a.index)
    # Every other layer is the same render too.
    for a, b in zip(plain, packed):
        for layer in ("rgb", "depth", "normal", "instanceid"):
            assert same_array(a.layer(layer), b.layer(layer)), (layer, a.index)
