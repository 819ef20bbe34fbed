"""lsds.validate: the findings of `lsds validate` on a clean and on a corrupted collection."""
import json

import pytest

import lsds
from helpers import run_lsds


def cli_report(collection):
    run = run_lsds("validate", collection, "--format", "json", check=False)
    assert run.returncode in (0, 1), run.stderr
    return run.returncode, json.loads(run.stdout)


def test_clean_collection(synth):
    report = lsds.validate(synth)
    assert report.ok and report.exit_code == 0
    assert report.counts["error"] == 0 and report.frames == 3
    assert "layer.depth-finite" in report.checks


def corrupt(collection):
    """A missing depth file and an object of an unknown class."""
    (collection / "depth" / "000001.exr").unlink()
    path = collection / "collection.json"
    doc = json.loads(path.read_text())
    doc["frames"][2]["objects"][0]["class_id"] = 99
    path.write_text(json.dumps(doc, indent=1))


def test_corrupted_collection(synth, copy_of):
    bad = copy_of(synth)
    corrupt(bad)
    report = lsds.validate(bad, jobs=1)
    assert not report.ok and report.exit_code == 1
    codes = {f.code for f in report.findings}
    assert {"structure.missing-file", "structure.class-id"} <= codes
    missing = next(f for f in report.findings if f.code == "structure.missing-file")
    assert missing.severity == "error"
    assert missing.location.frame == 1 and "depth" in str(missing.location)
    unknown = next(f for f in report.findings if f.code == "structure.class-id")
    assert unknown.location.json_pointer.startswith("/frames/2/objects/0")
    assert "99" in unknown.message
    assert str(unknown).startswith("error structure.class-id: ")
    # The same findings as the CLI's JSON report, which report.json() reproduces.
    exit_code, cli = cli_report(bad)
    assert exit_code == report.exit_code
    assert report.json()["counts"] == cli["counts"] and report.json()["verdict"] == cli["verdict"]
    cli_findings = [f for check in cli["checks"] for f in check.get("findings", [])]
    key = lambda f: json.dumps(f, sort_keys=True)  # noqa: E731
    assert sorted(map(key, (f.as_dict() for f in report.findings))) == sorted(map(key, cli_findings))


def test_options(synth, copy_of):
    bad = copy_of(synth)
    corrupt(bad)
    only = lsds.validate(bad, checks="structure.class-id")
    assert only.checks == ["structure.class-id"] and {f.code for f in only.findings} == {"structure.class-id"}
    assert lsds.validate(bad, checks="structure", frames="0:1").count("structure.missing-file") == 0
    assert lsds.validate(bad, fail_on="warning").exit_code == 1
    with pytest.raises(lsds.UsageError, match="did you mean"):
        lsds.validate(bad, checks="structure.clas-id")
    with pytest.raises(lsds.UsageError):
        lsds.validate(bad, frames="3:1")
    with pytest.raises(lsds.DataError):
        lsds.validate(bad / "nothing")


def test_frames_take_the_cli_grammar(synth, copy_of):
    """frames= takes every --frames form (and an int or a slice as the same range), parsed by the
    CLI's own parser: the frames checked and the findings are the CLI's for the same text."""
    bad = copy_of(synth)
    corrupt(bad)  # frame 1's depth file is missing
    forms = {"1": [1, "1", slice(1, 2)], "1:": ["1:", slice(1, None)], ":1": [":1", slice(None, 1)],
             "0:2": ["0:2", slice(0, 2)],
             "2": [2, "2"]}
    for text, arguments in forms.items():
        code, cli = cli_report_frames(bad, text)
        for argument in arguments:
            report = lsds.validate(bad, checks="structure", frames=argument)
            assert report.frames == cli["frames"], (text, argument)
            assert report.count("structure.missing-file") == sum(
                len(c.get("findings", [])) for c in cli["checks"] if c["id"] == "structure.missing-file"
            ), (text, argument)
            assert report.exit_code == code, (text, argument)
    assert lsds.validate(bad, checks="structure", frames="1").count("structure.missing-file") == 1
    assert lsds.validate(bad, checks="structure", frames=2).count("structure.missing-file") == 0
    # Bad ranges: the CLI's message, as a UsageError.
    cli_error = run_lsds("validate", bad, "--frames", "5:2", check=False)
    assert cli_error.returncode == 2
    for bad_range in ("5:2", slice(5, 2), "a:b", -1):
        with pytest.raises(lsds.UsageError, match="frames"):
            lsds.validate(bad, frames=bad_range)
    with pytest.raises(lsds.UsageError, match="step"):
        lsds.validate(bad, frames=slice(0, 3, 2))
    with pytest.raises(lsds.UsageError, match="float"):
        lsds.validate(bad, frames=1.5)
    # Outside the collection's frames: as the CLI, an error naming the valid range, never an empty
    # report.
    assert run_lsds("validate", bad, "--frames", "7", check=False).returncode == 2
    with pytest.raises(lsds.UsageError, match=r"frames 7: .*the collection"):
        lsds.validate(bad, frames=7)


def cli_report_frames(collection, text):
    run = run_lsds("validate", collection, "--checks", "structure", "--frames", text, "--format", "json",
                   check=False)
    assert run.returncode in (0, 1), run.stderr
    return run.returncode, json.loads(run.stdout)
