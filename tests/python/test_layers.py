"""Frame.layer and Frame.bundle: every flat layer of every layout bit for bit what
`lsds export-layers --to npy` writes, and the bundles' samples the same whichever layout stores them."""
import pathlib

import numpy as np
import pytest

import lsds
from helpers import exported, same_array


def check_layers_against_export(collection, workdir):
    c = lsds.open(collection)
    out = exported(collection, workdir)
    flat = [layer["name"] for layer in c.layers if not layer["deep"]]
    compared = 0
    for frame in c:
        for name in flat:
            if name not in frame.files:
                continue
            stem = pathlib.PurePosixPath(frame.files[name]).stem  # "000004", "000004_left"
            expected = np.load(out / name / (stem + ".npy"))
            got = frame.layer(name)
            assert same_array(got, expected), (collection, frame.index, name)
            # channels_first: the same values as (C, H, W), one-channel layers (1, H, W).
            planar = np.ascontiguousarray(np.moveaxis(expected.reshape(*expected.shape[:2], -1), 2, 0))
            assert same_array(frame.layer(name, channels_first=True), planar), (collection, name)
            assert got.dtype == (np.uint32 if name in ("classid", "instanceid") else np.float32)
            compared += 1
    return c, compared


def layout_of(c, name, absent="float"):
    """The layer table's `layout` of layer `name` (absent: the format's first layout)."""
    return next(layer.get("layout", absent) for layer in c.layers if layer["name"] == name)


def test_synth_layers_equal_the_npy_export(synth, workdir):
    c, compared = check_layers_against_export(synth, workdir)
    assert compared == len(c) * len([layer for layer in c.layers if not layer["deep"]])


def test_residual_layouts_equal_the_npy_export(demo_residual, workdir):
    c, compared = check_layers_against_export(demo_residual, workdir)
    assert layout_of(c, "worldposition") == "residual"
    assert layout_of(c, "motion") == "residual"
    assert compared >= 2 * 8


def test_float_layouts_equal_the_npy_export(demo_float, workdir):
    c, _ = check_layers_against_export(demo_float, workdir)
    assert layout_of(c, "worldposition") == "float"
    assert layout_of(c, "motion") == "float"


def test_rig_layers_equal_the_npy_export(rig, workdir):
    c, compared = check_layers_against_export(rig, workdir)
    assert c.rig is not None and [cam["name"] for cam in c.rig["cameras"]] == ["left", "right", "nir"]
    assert [f.rig_camera for f in c[:3]] == ["left", "right", "nir"]
    assert c[2].layer("depth").shape == (9, 12)  # the nir camera's own size
    assert compared > 0


def test_layouts_decode_to_the_same_values(demo_residual, demo_float, demo_compact):
    """The same render stored residual, float/full and compact: the decoded layers and bundles
    are identical."""
    residual, plain, compact = lsds.open(demo_residual), lsds.open(demo_float), lsds.open(demo_compact)
    layouts = [layout_of(c, "bundle", absent="full") for c in (residual, plain, compact)]
    assert layouts == ["residual", "full", "compact"]
    for a, b, c in zip(residual, plain, compact):
        for name in ("worldposition", "motion", "depth", "instanceid"):
            assert same_array(a.layer(name), b.layer(name)), name
        ba, bb, bc = a.bundle(), b.bundle(), c.bundle()
        assert same_array(ba.samples, bb.samples) and same_array(bc.samples, bb.samples)
        assert same_array(ba.offsets, bb.offsets) and same_array(bc.offsets, bb.offsets)


def test_layer_shapes_and_channel_order(synth):
    frame = lsds.open(synth)[0]
    assert frame.layer("depth").shape == (30, 40)
    normal = frame.layer("normal")
    assert normal.shape == (30, 40, 3)
    assert normal.flags["C_CONTIGUOUS"]
    norms = np.linalg.norm(normal.astype(np.float64), axis=2)
    ids = frame.layer("instanceid")
    assert np.allclose(norms[ids > 0], 1, atol=1e-5)


def test_bundle_arrays(demo_residual):
    frame = lsds.open(demo_residual)[0]
    bundle = frame.bundle()
    assert bundle.counts.shape == (16, 24) and bundle.counts.dtype == np.uint32
    assert (bundle.counts == 4).all()  # --spp 4: four samples in every pixel
    assert bundle.offsets.dtype == np.uint64 and bundle.offsets.shape == (16 * 24 + 1,)
    assert bundle.offsets[-1] == len(bundle.samples) == 4 * 16 * 24
    assert set(bundle.samples.dtype.names) == {"instanceid", "classid", "Z", "NX", "NY", "NZ", "SX", "SY"}
    assert bundle.samples["instanceid"].dtype == np.uint32
    assert bundle.samples["Z"].dtype == np.float32
    pixel = bundle.pixel(5, 7)
    first = int(bundle.offsets[7 * 24 + 5])
    assert same_array(pixel, bundle.samples[first:first + 4])
    # The instance id layer holds the closest surface at the pixel centre: nearly always one of
    # the pixel's sub-pixel samples.
    ids = frame.layer("instanceid")
    samples = bundle.samples["instanceid"].reshape(16, 24, 4)
    assert (samples == ids[..., None]).any(axis=2).mean() > 0.9
    with pytest.raises(IndexError):
        bundle.pixel(24, 0)


def test_mixed_pixels_example_of_the_docs(demo_residual):
    """docs/python.md's example: the pixels whose samples see two surfaces."""
    b = lsds.open(demo_residual)[0].bundle()
    ids = b.samples["instanceid"]
    pixel = np.repeat(np.arange(b.width * b.height), b.counts.ravel())
    first = ids[b.offsets[:-1][pixel]]
    mixed = np.zeros(b.width * b.height, bool)
    mixed[pixel[ids != first]] = True
    mixed = mixed.reshape(b.height, b.width)
    slow = [[len(set(b.pixel(x, y)["instanceid"].tolist())) > 1 for x in range(b.width)]
            for y in range(b.height)]
    assert (mixed == np.array(slow)).all() and mixed.any()
