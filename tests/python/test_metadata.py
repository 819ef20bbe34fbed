"""Metadata variants: collection.json's `metadata` list (the truth metadata.json and the perturbed
copies `lsds perturb-metadata` registers), listed by Collection.metadata_variants and chosen by
lsds.open(..., metadata=FILE) for Frame.metadata."""
import json

import pytest

import lsds
from helpers import run_lsds


def records(path):
    """The frame records of a metadata file, by frame index."""
    with open(path, encoding="utf-8") as f:
        return {record["index"]: record for record in json.load(f)["frames"]}


def test_variants_listed_and_chosen(demo_default, copy_of):
    collection = copy_of(demo_default)
    run_lsds("perturb-metadata", collection, "--seed", "7", "--sigma", "2,1")
    run_lsds("perturb-metadata", collection, "--seed", "8", "--sigma-alt", "3", "-o",
             collection / "altitude-noise.json")
    c = lsds.open(collection)
    variants = c.metadata_variants
    assert [(v["file"], v["perturbed"]) for v in variants] == [
        ("metadata.json", False), ("metadata.perturbed-7.json", True), ("altitude-noise.json", True)]
    assert c.metadata_variant == "metadata.json"
    truth = records(collection / "metadata.json")
    assert [f.metadata for f in c] == [truth[f.index] for f in c]

    for file in ("metadata.perturbed-7.json", "altitude-noise.json"):
        perturbed = lsds.open(collection, metadata=file)
        assert perturbed.metadata_variant == file
        expected = records(collection / file)
        assert [f.metadata for f in perturbed] == [expected[f.index] for f in perturbed]
        # The perturbation moved the measured pose, and the error it records is measured - true.
        frame = perturbed[1]
        assert frame.metadata["position"] != c[1].metadata["position"]
        moved = [a - b for a, b in zip(frame.metadata["position"], c[1].metadata["position"])]
        assert moved == pytest.approx(frame.metadata["error"]["position"], abs=1e-9)
        # Truth stays truth: the camera and layers do not change with the variant.
        assert perturbed[1].camera.cam_from_world.tolist() == c[1].camera.cam_from_world.tolist()

    with pytest.raises(lsds.UsageError, match=r"did you mean 'metadata.perturbed-7.json'") as error:
        lsds.open(collection, metadata="metadata.perturbed-8.json")
    assert "collection.json" in str(error.value)
