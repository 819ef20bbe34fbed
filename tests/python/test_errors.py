"""Errors are Python exceptions carrying the CLI's located message (file, JSON pointer, frame)."""
import json

import pytest

import lsds
from helpers import run_lsds


def cli_error(*args):
    """The message `lsds info` prints for the same input, without its 'lsds info: error: ' prefix."""
    run = run_lsds("info", *args, check=False)
    assert run.returncode == 2
    return run.stderr.strip().split("error: ", 1)[1]


def test_kinds():
    assert issubclass(lsds.UsageError, lsds.Error) and issubclass(lsds.UsageError, ValueError)
    assert issubclass(lsds.DataError, lsds.Error) and issubclass(lsds.InternalError, lsds.Error)
    assert issubclass(lsds.Error, Exception)


def test_missing_folder(tmp_path):
    with pytest.raises(lsds.DataError) as caught:
        lsds.open(tmp_path / "none")
    error = caught.value
    assert error.location.file == str(tmp_path / "none")
    assert error.message == "does not exist" and error.exit_code == 2
    assert str(error) == f"{tmp_path / 'none'}: does not exist" == cli_error(tmp_path / "none")


def test_json_syntax_error_names_line_and_column(synth, copy_of):
    bad = copy_of(synth)
    path = bad / "collection.json"
    path.write_text(path.read_text().replace('"frames"', '"frames" :: ', 1))
    with pytest.raises(lsds.DataError) as caught:
        lsds.open(bad)
    location = caught.value.location
    assert location.file == str(path) and location.line > 1 and location.column > 1
    assert str(caught.value).startswith(f"{path}:{location.line}:{location.column}: ")


def test_schema_error_names_the_json_pointer(synth, copy_of):
    bad = copy_of(synth)
    path = bad / "collection.json"
    doc = json.loads(path.read_text())
    doc["frames"][1]["time"] = "soon"
    path.write_text(json.dumps(doc))
    with pytest.raises(lsds.DataError) as caught:
        lsds.open(bad)
    assert caught.value.location.json_pointer == "/frames/1/time"
    assert f"{path}#/frames/1/time" in str(caught.value)


def test_unreadable_layer_names_the_file(synth, copy_of):
    bad = copy_of(synth)
    exr = bad / "depth" / "000002.exr"
    exr.write_bytes(exr.read_bytes()[:200])  # truncated
    c = lsds.open(bad)
    c[1].layer("depth")  # the other frames still read
    with pytest.raises(lsds.DataError) as caught:
        c[2].layer("depth")
    assert caught.value.location.file == str(exr)
    assert str(exr) in str(caught.value)


def test_wrong_size_layer_names_file_and_frame(synth, demo_residual, copy_of):
    bad = copy_of(synth)
    (bad / "depth" / "000000.exr").write_bytes((demo_residual / "depth" / "000000.exr").read_bytes())
    with pytest.raises(lsds.DataError) as caught:
        lsds.open(bad)[0].layer("depth")
    assert caught.value.location.frame == 0
    assert "24x16 but the frame's camera is 40x30" in str(caught.value)


def test_usage_errors(synth):
    c = lsds.open(synth)
    with pytest.raises(lsds.UsageError, match="did you mean 'depth'"):
        c[0].layer("dpth")
    with pytest.raises(ValueError):  # UsageError is a ValueError too
        c[0].bundle("depth")
    with pytest.raises(lsds.UsageError, match="threads"):
        lsds.open(synth, threads=0)
    try:
        c[0].layer("nothing")
    except lsds.Error as error:
        assert error.location.file is None and error.exit_code == 2
