#!/usr/bin/env python3
"""Hostile inputs of `lsds report` (docs/reliability.md): the validation report
(--validation-report) and the bundle statistics (--bundle-stats), malformed in
every value the page shows, plus the JSON mutations of the main corpus.

Uses hostile_corpus.py's machinery: each case runs in its own folder with a
60 s limit and must exit 2 naming the file and, for a value of the wrong type,
its JSON pointer; no crash, no internal error, every file of the folder
byte-identical and none added. Each case also runs under strace when it is
installed: the command may open, create, rename or remove nothing outside the
case folder but the system's own files (libraries, locale, /proc, /sys, /dev).

usage: report_corpus.py LSDS WORK [--filter SUBSTRING] [--list]
"""
import copy
import json
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_corpus import (Case, DEEP, corpus_main, fifo, json_mutations, run_case,  # noqa: E402
                            write)

SCRIPT = "<script>document.title='PWNED'</script>"

# A report with one finding of every location field (schemas/validate-report.schema.json).
VALIDATION = {
    "format": "lsds-validate-report", "format_version": "1.0", "collection": "C",
    "verdict": "fail", "fail_on": "error", "frames": 2, "files_decoded": 0,
    "bytes_decoded": 0, "seconds": 0,
    "counts": {"error": 1, "warning": 0, "info": 0},
    "checks": [{"id": "layer.depth-finite", "severity": "error", "tolerance": "",
                "count": 1, "findings": [{
                    "severity": "error", "check": "layer.depth-finite", "object": "box#0",
                    "location": {"file": "depth/000001.exr", "json_pointer": "/frames/1",
                                 "line": 3, "column": 4, "frame": 1, "pixel": [3, 4]},
                    "message": "depth is NaN"}]}],
    "statistics": {},
}

FINDING = "/checks/0/findings/0"
# (label, JSON pointer set, value, pointer the error must name)
VALIDATION_VALUES = [
    ("count-string", "/checks/0/count", "1", "/checks/0/count"),
    ("count-object", "/checks/0/count", {"n": 1}, "/checks/0/count"),
    ("counts-error-string", "/counts/error", "1", "/counts/error"),
    ("counts-not-object", "/counts", [1, 0, 0], "/counts"),
    ("verdict-number", "/verdict", 1, "/verdict"),
    ("verdict-script", "/verdict", SCRIPT, "/verdict"),
    ("fail-on-object", "/fail_on", {}, "/fail_on"),
    ("frames-string", "/frames", "2", "/frames"),
    ("frames-bool", "/frames", True, "/frames"),
    ("checks-object", "/checks", {}, "/checks"),
    ("check-string", "/checks/0", "check", "/checks/0"),
    ("check-id-script", "/checks/0/id", SCRIPT, "/checks/0/id"),
    ("check-id-number", "/checks/0/id", 7, "/checks/0/id"),
    ("severity-array", "/checks/0/severity", [], "/checks/0/severity"),
    ("findings-string", "/checks/0/findings", "none", "/checks/0/findings"),
    ("finding-number", FINDING, 1, FINDING),
    ("object-number", FINDING + "/object", 5, FINDING + "/object"),
    ("message-null", FINDING + "/message", None, FINDING + "/message"),
    ("location-string", FINDING + "/location", "here", FINDING + "/location"),
    ("file-array", FINDING + "/location/file", [1], FINDING + "/location/file"),
    ("json-pointer-object", FINDING + "/location/json_pointer", {},
     FINDING + "/location/json_pointer"),
    ("frame-string", FINDING + "/location/frame", "1", FINDING + "/location/frame"),
    ("frame-float", FINDING + "/location/frame", 1.5, FINDING + "/location/frame"),
    ("frame-huge", FINDING + "/location/frame", 18446744073709551615,
     FINDING + "/location/frame"),
    ("line-string", FINDING + "/location/line", "3", FINDING + "/location/line"),
    ("pixel-string", FINDING + "/location/pixel", "3, 4", FINDING + "/location/pixel"),
    ("pixel-script", FINDING + "/location/pixel", [SCRIPT, 4], FINDING + "/location/pixel/0"),
    ("pixel-object", FINDING + "/location/pixel", [3, {"y": 4}], FINDING + "/location/pixel/1"),
    ("pixel-short", FINDING + "/location/pixel", [3], FINDING + "/location/pixel"),
    ("pixel-huge", FINDING + "/location/pixel", [3, 18446744073709551615],
     FINDING + "/location/pixel/1"),
    ("format-number", "/format", 1, "/format"),
    ("format-other", "/format", "lsds-bundle-stats", "/format"),
]

# (label, function(stats) -> None, pointer)
BUNDLE_VALUES = [
    ("format-number", lambda s: s.__setitem__("format", 1), "/format"),
    ("bundle-layer-number", lambda s: s.__setitem__("bundle_layer", 3), "/bundle_layer"),
    ("frame-range-string", lambda s: s.__setitem__("frame_range", "0:2"), "/frame_range/first"),
    ("frame-range-end-string", lambda s: s["frame_range"].__setitem__("end", "2"),
     "/frame_range/end"),
    ("summary-array", lambda s: s.__setitem__("summary", []), "/summary"),
    ("class-id-string", lambda s: s["summary"]["class_mixing"]["classes"].__setitem__(0, "1"),
     "/summary/class_mixing/classes/0"),
    ("objects-float-huge", lambda s: s["summary"]["by_object_size"][0].__setitem__("objects", 1e300),
     "/summary/by_object_size/0/objects"),
    ("max-pixels-string", lambda s: s["summary"]["by_object_size"][0].__setitem__("max_pixels", "9"),
     "/summary/by_object_size/0/max_pixels"),
]


def set_pointer(document, pointer, value):
    parts = [p.replace("~1", "/").replace("~0", "~") for p in pointer.split("/")[1:]]
    node = document
    for part in parts[:-1]:
        node = node[int(part)] if isinstance(node, list) else node[part]
    last = parts[-1]
    if isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value


def pointer_place(file, pointer):
    return re.escape(file + "#" + pointer) + ":"


def build_cases(lsds, work):
    cases = []
    base = os.path.join(work, "base")
    collection = os.path.join(base, "C")
    stats_file = os.path.join(base, "stats.json")
    if not os.path.isdir(collection):
        os.makedirs(base, exist_ok=True)
        subprocess.run([lsds, "synth", collection, "--count", "2", "--size", "32x24",
                        "--samples-per-axis", "2"], check=True, stdout=subprocess.DEVNULL)
    if not os.path.isfile(stats_file):
        subprocess.run([lsds, "bundles", collection, "-o", stats_file], check=True,
                       stdout=subprocess.DEVNULL)
    stats = json.load(open(stats_file))
    validation_text = json.dumps(VALIDATION, indent=1).encode()
    stats_text = json.dumps(stats, indent=1).encode()

    def add(case, *setups):
        case.setup = [lambda d: shutil.copytree(collection, os.path.join(d, "C"),
                                                symlinks=True)] + list(setups)
        cases.append(case)

    with_validation = "report {d}/C -o {d}/page.html --validation-report {d}/v.json".split()
    with_stats = "report {d}/C -o {d}/page.html --bundle-stats {d}/s.json".split()

    # --- values of the wrong type or range, at their JSON pointer -------------
    for label, pointer, value, where in VALIDATION_VALUES:
        document = copy.deepcopy(VALIDATION)
        set_pointer(document, pointer, value)
        data = json.dumps(document).encode()
        add(Case("validation-report/" + label, with_validation, names="v.json",
                 place=pointer_place("v.json", where)),
            lambda d, data=data: write(os.path.join(d, "v.json"), data))
    add(Case("validation-report/not-an-object", with_validation, names="v.json",
             place=pointer_place("v.json", "/format")),
        lambda d: write(os.path.join(d, "v.json"), b"[1, 2]"))
    for label, mutate, where in BUNDLE_VALUES:
        document = copy.deepcopy(stats)
        mutate(document)
        data = json.dumps(document).encode()
        add(Case("bundle-stats/" + label, with_stats, names="s.json",
                 place=pointer_place("s.json", where)),
            lambda d, data=data: write(os.path.join(d, "s.json"), data))

    # --- the JSON mutations of the main corpus and files that are not files ---
    for file, text, line in (("v.json", validation_text, with_validation),
                             ("s.json", stats_text, with_stats)):
        group = "validation-report" if file == "v.json" else "bundle-stats"
        for label, mutate, place in json_mutations():
            if label in ("deep-inside-frames", "frames-not-array", "number-overflow"):
                continue  # they edit collection.json's frames: not in these files
            if label == "not-an-object":
                place = pointer_place(file, "/format")
            add(Case("%s/json-%s" % (group, label), line, names=file, place=place),
                lambda d, file=file, data=mutate(text): write(os.path.join(d, file), data))
        add(Case("%s/json-number-overflow" % group, line, names=file,
                 place=r":1:\d+: invalid JSON: number out of range"),
            lambda d, file=file, text=text: write(os.path.join(d, file),
                                                  b"{\"x\": 1e99999, " + text[1:]))
        deep = b"{\"checks\": [" + b"{\"a\": [" * DEEP + b"]}" * DEEP + b"]}"
        add(Case("%s/deep-in-place" % group, line, names=file, place=r":1:\d+: nesting deeper"),
            lambda d, file=file: write(os.path.join(d, file), deep))
        add(Case("%s/fifo" % group, line, names=file),
            lambda d, file=file: fifo(os.path.join(d, file)))
        add(Case("%s/folder" % group, line, names=file),
            lambda d, file=file: os.mkdir(os.path.join(d, file)))
        add(Case("%s/missing" % group, line, names=file))
    return cases


# System files any process opens: the dynamic loader, libraries, locale, the
# kernel's views. Anything else outside the case folder is a finding.
SYSTEM = ("/usr/", "/lib/", "/lib64/", "/etc/", "/proc/", "/sys/", "/dev/")
TOUCH = re.compile(r'^\d+\s+(open|openat|creat|mkdir|mkdirat|rename|renameat2?|unlink|unlinkat|'
                   r'rmdir|link|linkat|symlink|symlinkat|truncate|chmod|fchmodat|utimensat)'
                   r'\((?:AT_FDCWD, |\d+, )?"([^"]*)"(?:.*?, (?:AT_FDCWD, |\d+, )?"([^"]*)")?')


def outside(trace, case_dir, lsds):
    """Paths the traced run touched outside the case folder and the system."""
    allowed = (os.path.realpath(case_dir) + os.sep, os.path.dirname(lsds) + os.sep)
    found = []
    for line in open(trace, errors="replace"):
        m = TOUCH.match(line)
        if not m or re.search(r"\) = -1 [A-Z]", line):
            continue  # not a path call, or it failed (a probe of a missing file)
        for path in filter(None, m.group(2, 3)):
            if not path.startswith("/") or path.startswith(SYSTEM):
                continue
            real = os.path.realpath(path)
            if not (real + os.sep).startswith(allowed) and not real.startswith(SYSTEM):
                found.append(path)
    return sorted(set(found))


def main():
    strace = shutil.which("strace")

    # The unmutated inputs make a page: the cases fail for their mutation.
    def prepare(lsds, work):
        base = os.path.join(work, "base")
        page = os.path.join(work, "baseline.html")
        valid = os.path.join(work, "valid.json")
        write(valid, json.dumps(VALIDATION))
        baseline = subprocess.run([lsds, "report", os.path.join(base, "C"), "-o", page, "--force",
                                   "--validation-report", valid, "--bundle-stats",
                                   os.path.join(base, "stats.json")], capture_output=True)
        if baseline.returncode != 0:
            return "baseline: exit %d\n%s" % (baseline.returncode, baseline.stderr.decode())
        if not strace:
            print("note: strace is not installed: paths outside the case folders are not checked")
        os.makedirs(os.path.join(work, "traces"), exist_ok=True)
        return None

    def run(lsds, work, case):
        trace = os.path.join(work, "traces", case.name.replace("/", "__") + ".log")
        runner = lsds
        if strace:
            # strace exits with the command's code (and its signal).
            runner = strace
            case.args = ["-f", "-qq", "-e", "trace=%file", "-o", trace, lsds] + case.args
            # LeakSanitizer cannot work under ptrace: in a sanitizer build (make test-asan)
            # it would abort every case; address and UB checks stay on.
            options = os.environ.get("ASAN_OPTIONS", "")
            case.env = dict(case.env, ASAN_OPTIONS=(options + ":detect_leaks=0").lstrip(":"))
        problem, last = run_case(runner, work, case)
        if strace and os.path.exists(trace):
            d = os.path.join(work, "cases", case.name.replace("/", "__"))
            touched = outside(trace, d, lsds)
            if touched:
                problem = "; ".join(filter(None, [problem, "touched outside its folder: " +
                                                  ", ".join(touched[:5])]))
            elif not problem:
                os.remove(trace)
        return problem, last

    return corpus_main(__doc__, build_cases, run=run, prepare=prepare)


if __name__ == "__main__":
    sys.exit(main())
