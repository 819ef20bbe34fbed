#!/usr/bin/env python3
"""Build the defect corpus of `lsds validate`: a good synthetic collection and one defective copy per
check (truncated EXR, wrong channel type, NaN depth, non-unit normals, bbox off by one pixel, missing
layer file, unknown class id, schema violation, depth in cm, FOV off by 10 degrees, y axis flipped, ...).

The corruptions themselves are C++ (tests/validate/corruptions.cc, through libs/exr: there is no
Python OpenEXR module on the build machines); this script drives the helper that applies them and,
with --verify, runs `lsds validate --format json` on every collection and checks that the good one
passes clean and each defective one is reported at its expected check id and location.

    scripts/make-bad-corpus.py --out /tmp/corpus [--only nan-depth ...] [--verify]
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
BUILD = os.path.join(HERE, "..", "build", "release")


def matches(finding, expected):
    location = finding["location"]
    if location.get("file") != expected["file"]:
        return False
    for key in ("frame", "json_pointer", "pixel"):
        if key in expected and location.get(key) != expected[key]:
            return False
    return True


def validate(lsds, collection):
    run = subprocess.run([lsds, "validate", "--format", "json", "--fail-on", "warning", collection],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if run.returncode == 2:
        raise RuntimeError(f"lsds validate {collection}: exit 2: {run.stderr.strip()}")
    return run.returncode, json.loads(run.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="corpus folder to create")
    parser.add_argument("--tool", default=os.path.join(BUILD, "tests", "validate", "lsds_make_bad_corpus"))
    parser.add_argument("--lsds", default=os.path.join(BUILD, "tools", "lsds"))
    parser.add_argument("--only", action="append", default=[], help="build only this corruption")
    parser.add_argument("--force", action="store_true", help="replace an existing --out folder")
    parser.add_argument("--verify", action="store_true", help="validate every collection of the corpus")
    args = parser.parse_args()

    if os.path.exists(args.out):
        if not args.force:
            sys.exit(f"{args.out}: exists (use --force to replace it)")
        shutil.rmtree(args.out)
    command = [args.tool, args.out]
    for name in args.only:
        command += ["--only", name]
    subprocess.run(command, check=True)
    with open(os.path.join(args.out, "manifest.json")) as f:
        manifest = json.load(f)
    print(f"{args.out}: good + {len(manifest)} defective collections")
    if not args.verify:
        return 0

    failures = 0
    code, report = validate(args.lsds, os.path.join(args.out, "good"))
    total = sum(report["counts"].values())
    if code != 0 or total != 0:
        print(f"FAIL good: exit {code}, {total} finding(s)")
        failures += 1
    for entry in manifest:
        expected = entry["expected"]
        code, report = validate(args.lsds, os.path.join(args.out, entry["name"]))
        checks = [c for c in report["checks"] if c["id"] == expected["check"]]
        findings = [f for c in checks for f in c["findings"]]
        # An info check (a statistic) is reported but fails nothing by itself.
        info = any(c.get("severity") == "info" for c in checks)
        ok = (info or code == 1) and any(matches(f, expected) for f in findings)
        if not ok:
            failures += 1
        print(f"{'ok  ' if ok else 'FAIL'} {entry['name']:28} -> {expected['check']} at {expected['file']}"
              + (f" frame {expected['frame']}" if "frame" in expected else "")
              + (f" #{expected['json_pointer']}" if "json_pointer" in expected else "")
              + (f" pixel {tuple(expected['pixel'])}" if "pixel" in expected else ""))
    print(f"{len(manifest) + 1 - failures}/{len(manifest) + 1} collections reported as expected")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
