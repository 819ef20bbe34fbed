#!/usr/bin/env python3
"""The malformed-input corpus of docs/reliability.md, run through the CLI.

Builds every case into WORK (a folder in the build tree): a small synthetic
collection, scene files, and one mutation per case (a truncated or deeply
nested JSON file, a FIFO where a file belongs, an output aimed at an input,
...). Each case runs one lsds command with a time limit and must:
  - exit with its expected code (2 bad input, 1 data findings), never >= 128
    (a signal: crash, abort) and never 70 (an internal error);
  - print no sanitizer report;
  - name the file (and, where the case says so, the place) on stderr;
  - finish within the time limit (a FIFO must not block);
  - leave every file of the case byte-identical and add none (no partial
    output, inputs untouched).

usage: hostile_corpus.py LSDS WORK [--filter SUBSTRING] [--list]
"""
import hashlib
import os
import re
import shutil
import stat
import subprocess
import sys
import time

TIME_LIMIT_S = 60

DEEP = 100000  # the depth of the nesting cases (the limit is 256)


class Case:
    def __init__(self, name, args, expect=(2,), names=None, place=None,
                 env=None):
        self.name = name
        self.args = args          # argv after the binary; {d} = case folder
        self.expect = expect      # accepted exit codes
        self.names = names        # a substring stderr must contain
        self.place = place        # a regex stderr must match (line:col, #/...)
        self.env = env or {}
        self.setup = []           # functions(case_dir) run before the case


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(path, mode) as f:
        f.write(data)


def fifo(path):
    if os.path.lexists(path):
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path)
        else:
            os.remove(path)
    os.mkfifo(path)


def tree_state(root):
    """Every entry under root: path -> sha256 (files), 'dir', 'fifo', link."""
    state = {}
    for folder, dirs, files in os.walk(root):
        for d in dirs:
            p = os.path.join(folder, d)
            state[p] = "link:" + os.readlink(p) if os.path.islink(p) else "dir"
        for f in files:
            p = os.path.join(folder, f)
            st = os.lstat(p)
            if stat.S_ISLNK(st.st_mode):
                state[p] = "link:" + os.readlink(p)
            elif stat.S_ISFIFO(st.st_mode):
                state[p] = "fifo"
            else:
                state[p] = file_digest(p, st.st_size)
    return state


def file_digest(path, size):
    """sha256 of the file's size and of its data extents with their offsets. A sparse 1 GiB input
    hashes its few data blocks instead of a gigabyte of zeros (reading those cost the decoder corpus
    about 170 of its 210 seconds). Any write, zeros into a hole included, allocates an extent and
    changes the digest; on a file system without SEEK_DATA the whole file is one extent."""
    digest = hashlib.sha256(b"%d" % size)
    with open(path, "rb") as fh:
        offset = 0
        while offset < size:
            try:
                start = os.lseek(fh.fileno(), offset, os.SEEK_DATA)
            except OSError:  # ENXIO: nothing but a hole from offset to the end
                break
            end = os.lseek(fh.fileno(), start, os.SEEK_HOLE)
            digest.update(b"@%d:" % start)
            fh.seek(start)
            left = end - start
            while left > 0:
                block = fh.read(min(left, 1 << 20))
                if not block:
                    break
                digest.update(block)
                left -= len(block)
            offset = end
    return digest.hexdigest()


# --- mutations of a JSON file -------------------------------------------------

def json_mutations():
    """(label, function(original bytes) -> new bytes, place regex or None)."""
    return [
        ("empty", lambda b: b"", None),
        ("truncated", lambda b: b[: len(b) // 2], r":\d+:\d+"),
        ("not-an-object", lambda b: b"[1, 2, 3]\n", None),
        ("garbage", lambda b: bytes(range(256)) * 4, r":\d+:\d+"),
        ("deep-arrays", lambda b: b"{\"frames\": " + b"[" * DEEP + b"]" * DEEP
         + b"}", "nesting deeper"),
        ("deep-objects", lambda b: b"{\"a\": " + b"{\"a\": " * DEEP + b"1"
         + b"}" * DEEP + b"}", "nesting deeper"),
        ("deep-inside-frames", lambda b: b.replace(b"\"frames\": [",
                                                     b"\"frames\": [" + b"[" * DEEP + b"]" * DEEP + b",", 1), "nesting deeper"),
        ("nul-bytes", lambda b: b[:40] + b"\0\0\0" + b[40:], r":\d+:\d+"),
        ("number-overflow", lambda b: b.replace(b"\"frames\": [", b"\"x\": 1e99999, \"frames\": [", 1),
         "number overflow"),
        ("frames-not-array", lambda b: re.sub(rb"\"frames\": \[", b"\"frames\": {\"x\": [", b, count=1)
         + b"", None),
    ]


def build_cases(lsds, work):
    cases = []
    base = os.path.join(work, "base")
    collection = os.path.join(base, "C")
    if not os.path.isdir(collection):
        os.makedirs(base, exist_ok=True)
        subprocess.run([lsds, "synth", collection, "--count", "2", "--size",
                        "32x24", "--samples-per-axis", "2"], check=True,
                       stdout=subprocess.DEVNULL)
    examples = os.path.join(os.path.dirname(os.path.abspath(__file__)),
                            "..", "..", "examples")
    scene_text = open(os.path.join(examples, "uav_survey.lscene")).read()
    capture_text = open(os.path.join(examples, "demo_survey.lcap")).read()

    def copy_collection(d):
        shutil.copytree(collection, os.path.join(d, "C"), symlinks=True)

    def scene_files(d):
        write(os.path.join(d, "s.lscene"), scene_text)
        write(os.path.join(d, "c.lcap"), capture_text)

    def add(case, *setups):
        case.setup = [copy_collection, scene_files] + list(setups)
        cases.append(case)
        return case

    # --- 1. outputs aimed at inputs: refused with or without --force ---------
    protection = [
        ("convert-onto-collection", "convert {d}/C --to coco -o {d}/C --force"),
        ("convert-onto-collection-noforce", "convert {d}/C --to yolo -o {d}/C"),
        ("convert-inside-collection", "convert {d}/C --to coco -o {d}/C/out"),
        ("convert-onto-layer-folder", "convert {d}/C --to coco -o {d}/C/rgb --force"),
        ("convert-containing-collection", "convert {d}/C --to coco -o {d} --force"),
        ("convert-dotdot-collection", "convert {d}/C --to coco -o {d}/C/../C --force"),
        ("validate-onto-collection-json", "validate {d}/C -o {d}/C/collection.json --force"),
        ("validate-onto-layer-file", "validate {d}/C -o {d}/C/depth/000000.exr --force"),
        ("validate-onto-metadata", "validate {d}/C --format junit -o {d}/C/metadata.json --force"),
        ("bundles-onto-collection-json", "bundles {d}/C -o {d}/C/collection.json --force"),
        ("bundles-stats-inside-collection", "bundles {d}/C -o {d}/C/stats.json"),
        ("bundles-mixed-map-onto-layer", "bundles {d}/C --mixed-map {d}/C/rgb/000000.exr --force"),
        ("bundles-write-layers-unregistered-folder", "bundles {d}/C --write-layers majority --force"),
        ("backproject-onto-collection", "backproject {d}/C -o {d}/C --fuse --force"),
        ("backproject-inside-collection", "backproject {d}/C -o {d}/C/cloud.ply --fuse"),
        ("report-onto-collection-json", "report {d}/C -o {d}/C/collection.json --force"),
        ("report-inside-collection", "report {d}/C -o {d}/C/report.html"),
        ("perturb-onto-collection-json", "perturb-metadata {d}/C --sigma 1 --seed 3 -o {d}/C/collection.json --force"),
        ("perturb-onto-truth-metadata", "perturb-metadata {d}/C --sigma 1 --seed 3 -o {d}/C/metadata.json --force"),
        ("perturb-into-layer-folder", "perturb-metadata {d}/C --sigma 1 --seed 3 -o {d}/C/rgb/m.json"),
        ("perturb-report-onto-layer", "perturb-metadata {d}/C --sigma 1 --seed 3 --report {d}/C/depth/000001.exr --force"),
        ("plan-onto-scene", "plan {d}/s.lscene {d}/c.lcap -o {d}/s.lscene --force"),
        ("plan-onto-capture", "plan {d}/s.lscene {d}/c.lcap -o {d}/c.lcap --force"),
        ("generate-onto-scene", "generate {d}/s.lscene {d}/c.lcap -o {d}/s.lscene --force"),
        ("generate-containing-scene", "generate {d}/s.lscene {d}/c.lcap -o {d} --force"),
        ("merge-onto-shard", "merge {d}/C -o {d}/C --force"),
        ("merge-inside-shard", "merge {d}/C -o {d}/C/merged"),
        ("import-onto-source", "import airsim {d}/C -o {d}/C --force"),
        ("evaluate-onto-collection-json", "evaluate {d}/C --coverage -o {d}/C/collection.json --force"),
        ("evaluate-inside-collection", "evaluate {d}/C --coverage -o {d}/C/eval.json"),
        ("evaluate-onto-predictions", "evaluate {d}/C --predictions {d}/p.json -o {d}/p.json --force"),
        ("evaluate-suggest-onto-collection", "evaluate {d}/C --predictions {d}/p.json -o {d}/e.json --suggest {d}/C/next.lcap"),
        ("convert-through-symlink", "convert {d}/L --to coco -o {d}/C --force"),
        ("convert-into-symlinked-collection", "convert {d}/C --to coco -o {d}/L/out"),
    ]
    for name, line in protection:
        setups = []
        if "symlink" in name:
            setups.append(lambda d: os.symlink("C", os.path.join(d, "L")))
        if "unregistered-folder" in name:
            setups.append(lambda d: write(os.path.join(d, "C", "majority", "notes.txt"), "mine\n"))
        if name.startswith("evaluate") and "predictions" in line:
            setups.append(lambda d: write(os.path.join(d, "p.json"), "[]\n"))
        names = "an input of lsds"
        if "unregistered-folder" in name:
            names = "not one of its derived layers"
        add(Case("protect/" + name, line.split(), names=names), *setups)

    # --- 2. collection.json broken, every reading command ----------------------
    readers = {
        "info": "info {d}/C",
        "validate": "validate {d}/C",
        "convert": "convert {d}/C --to coco -o {d}/out",
        "bundles": "bundles {d}/C -o {d}/stats.json",
        "backproject": "backproject {d}/C -o {d}/cloud.ply --fuse",
        "report": "report {d}/C -o {d}/report.html",
        "perturb": "perturb-metadata {d}/C --sigma 1 --seed 3 -o {d}/m.json",
        "evaluate": "evaluate {d}/C --coverage -o {d}/e.json",
    }
    collection_json = open(os.path.join(collection, "collection.json"), "rb").read()
    for label, mutate, place in json_mutations():
        data = mutate(collection_json)
        for command, line in readers.items():
            if label == "deep-inside-frames" and command == "perturb":
                continue  # perturb-metadata reads only collection.json's header
            # perturb-metadata only scans past the frames of collection.json:
            # deep frames are never parsed; it names the schema error instead.
            where = r"collection.json#/" if (label == "deep-arrays" and
                                             command == "perturb") else place
            add(Case("collection-json/%s/%s" % (label, command), line.split(),
                     names="collection.json", place=where),
                lambda d, data=data: write(os.path.join(d, "C", "collection.json"), data))
    for command, line in readers.items():
        add(Case("collection-json/fifo/" + command, line.split(),
                 names="collection.json"),
            lambda d: fifo(os.path.join(d, "C", "collection.json")))
        add(Case("collection-json/folder/" + command, line.split(),
                 names="collection.json"),
            lambda d: (os.remove(os.path.join(d, "C", "collection.json")),
                       os.mkdir(os.path.join(d, "C", "collection.json"))))

    # lsds evaluate's predictions file: the JSON mutations, a FIFO, a folder.
    predictions = (b'[{"image_id": 1, "category_id": 1, "bbox": [1, 2, 3, 4], "score": 0.9},\n'
                   b' {"image_id": 2, "category_id": 1, "bbox": [5, 6, 7, 8], "score": 0.5}]\n')
    evaluate_line = "evaluate {d}/C --predictions {d}/p.json -o {d}/e.json".split()
    for label, mutate, place in json_mutations():
        if label in ("deep-inside-frames", "number-overflow", "frames-not-array"):
            continue  # about collection.json's frames
        add(Case("predictions/" + label, evaluate_line, names="p.json", place=place),
            lambda d, data=mutate(predictions): write(os.path.join(d, "p.json"), data))
    add(Case("predictions/fifo", evaluate_line, names="p.json"),
        lambda d: fifo(os.path.join(d, "p.json")))
    add(Case("predictions/folder", evaluate_line, names="p.json"),
        lambda d: os.mkdir(os.path.join(d, "p.json")))
    add(Case("predictions/nan-score", evaluate_line, names="p.json", place=r"#/0/score"),
        lambda d: write(os.path.join(d, "p.json"), predictions.replace(b"0.9", b"NaN")))

    # --- 3. layer files broken -------------------------------------------------
    layer_readers = {
        "validate": ("validate {d}/C", (1, 2)),
        "convert": ("convert {d}/C --to coco -o {d}/out", (2,)),
        "backproject": ("backproject {d}/C -o {d}/cloud.ply --fuse", (2,)),
        "convert-images": ("convert {d}/C --to yolo --images png -o {d}/out", (2,)),
        "bundles": ("bundles {d}/C -o {d}/stats.json", (2,)),
    }
    # (lsds report shows an unreadable layer in the page, by design: not here.)
    layer_of = {"validate": "depth", "convert": "instanceid",
                "backproject": "depth", "convert-images": "rgb",
                "bundles": "bundle"}
    layer_mutations = [
        ("fifo", lambda p: fifo(p)),
        ("empty", lambda p: write(p, b"")),
        ("truncated", lambda p: write(p, open(p, "rb").read()[:200])),
        ("garbage", lambda p: write(p, b"v/1\x01" + bytes(range(256)) * 8)),
        ("folder", lambda p: (os.remove(p), os.mkdir(p))),
        ("missing", lambda p: os.remove(p)),
    ]
    for label, mutate in layer_mutations:
        for command, (line, expect) in layer_readers.items():
            layer = layer_of[command]
            add(Case("layer/%s/%s" % (label, command), line.split(),
                     expect=expect, names="%s/000000.exr" % layer),
                lambda d, mutate=mutate, layer=layer:
                    mutate(os.path.join(d, "C", layer, "000000.exr")))

    # --- 4. metadata broken ----------------------------------------------------
    metadata_json = open(os.path.join(collection, "metadata.json"), "rb").read()
    metadata_readers = {
        "perturb": ("perturb-metadata {d}/C --sigma 1 --seed 3 -o {d}/m.json", (2,)),
        "backproject": ("backproject {d}/C -o {d}/cloud.ply --fuse --use-metadata metadata.json", (2,)),
    }
    for label, mutate, place in json_mutations()[:8]:
        data = mutate(metadata_json)
        for command, (line, expect) in metadata_readers.items():
            add(Case("metadata/%s/%s" % (label, command), line.split(),
                     expect=expect, names="metadata.json"),
                lambda d, data=data: write(os.path.join(d, "C", "metadata.json"), data))
    for command, (line, expect) in metadata_readers.items():
        add(Case("metadata/fifo/" + command, line.split(), expect=expect,
                 names="metadata.json"),
            lambda d: fifo(os.path.join(d, "C", "metadata.json")))

    # --- 5. LSCENE / LCAP broken -----------------------------------------------
    scene_mutations = [
        ("deep-braces", "s.lscene", "LSCENE = ONE(S)\nS = skybox{color:" + "{b:" * DEEP + "1" + "}" * DEEP + "}\n", r":2:\d+: nesting deeper"),
        ("deep-lists", "s.lscene", "LSCENE = ONE(S)\nS = skybox{color:" + "[" * DEEP + "1" + "]" * DEEP + "}\n", r":2:\d+: nesting deeper"),
        ("deep-json", "s.lscene", "{\"a\": " + "[" * DEEP + "]" * DEEP + "}\n", r":1:\d+: nesting deeper"),
        ("deep-json-objects", "s.lscene", "{\"a\": " + "{\"b\": " * DEEP + "1" + "}" * DEEP + "}\n", r":1:\d+: nesting deeper"),
        ("unterminated-string", "s.lscene", "scene { name: \"abc\n }\n", r":\d+:\d+"),
        ("unclosed-brace", "s.lscene", scene_text.rstrip().rstrip("}") + "\n", r":\d+:\d+"),
        ("garbage", "s.lscene", bytes(range(1, 256)) * 4, r":\d+:\d+"),
        ("empty-json", "s.lscene", "{", r":\d+:\d+"),
        ("json-number-overflow", "s.lscene", "{\"a\": 1e999999}", r":1:7: invalid JSON: number (out of range: number )?overflow"),
        ("capture-deep-braces", "c.lcap", "LCAP = ONE(CO)\nCO = camera{x:" + "{b:" * DEEP + "1" + "}" * DEEP + "}\n", r":2:\d+: nesting deeper"),
        ("capture-deep-json", "c.lcap", "{\"a\": " + "[" * DEEP + "]" * DEEP + "}\n", r":1:\d+: nesting deeper"),
        ("capture-garbage", "c.lcap", b"\xff\xfe\x00" * 100, None),
    ]
    scene_commands = {
        "plan": "plan {d}/s.lscene {d}/c.lcap -o {d}/plan.json",
        "plan-emit-json": "plan {d}/s.lscene {d}/c.lcap --emit-json -o {d}/plan.json",
        "generate": "generate {d}/s.lscene {d}/c.lcap -o {d}/out -q",
    }
    for label, file, data, place in scene_mutations:
        for command, line in scene_commands.items():
            add(Case("scene/%s/%s" % (label, command), line.split(),
                     names=file, place=place),
                lambda d, file=file, data=data: write(os.path.join(d, file), data))
    for file in ("s.lscene", "c.lcap"):
        for command, line in scene_commands.items():
            add(Case("scene/fifo-%s/%s" % (file, command), line.split(), names=file),
                lambda d, file=file: fifo(os.path.join(d, file)))
            add(Case("scene/folder-%s/%s" % (file, command), line.split(), names=file),
                lambda d, file=file: (os.remove(os.path.join(d, file)),
                                      os.mkdir(os.path.join(d, file))))

    # --- 6. plans (generate --plan) ----------------------------------------------
    plan_mutations = [
        ("deep", "{\"frames\": " + "[" * DEEP + "]" * DEEP + "}", r":1:\d+: nesting deeper"),
        ("truncated", "{\"frames\": [{\"index\": 0, ", r":\d+:\d+"),
        ("garbage", "\x01\x02 nonsense", r":\d+:\d+"),
        ("not-an-object", "[]", None),
    ]
    for label, data, place in plan_mutations:
        add(Case("plan-file/" + label,
                 "generate --plan {d}/p.json -o {d}/out -q".split(),
                 names="p.json", place=place),
            lambda d, data=data: write(os.path.join(d, "p.json"), data))
    add(Case("plan-file/fifo", "generate --plan {d}/p.json -o {d}/out -q".split(),
             names="p.json"),
        lambda d: fifo(os.path.join(d, "p.json")))

    # --- 7. resource limits --------------------------------------------------------
    add(Case("limits/demo-size-huge",
             "generate --demo --demo-size 200000x200000 -o {d}/out -q".split(),
             names="--demo-size", place="memory budget"))
    add(Case("limits/demo-size-over-env-budget",
             "generate --demo --demo-size 256x256 -o {d}/out -q".split(),
             names="--demo-size", place="memory budget",
             env={"LSDS_MEMORY_BUDGET": "1M"}))
    add(Case("limits/memory-budget-flag-bad",
             "generate --demo --memory-budget lots -o {d}/out -q".split(),
             names="--memory-budget"))
    # Every command that decodes layers checks the decode against the budget
    # (--memory-budget is a flag of every command), naming the layer file (the
    # first one decoded, whichever frame and layer that is).
    for command, (line, expect) in layer_readers.items():
        add(Case("limits/layer-over-budget/%s" % command,
                 (line + " --memory-budget 1K").split(), expect=expect,
                 names=".exr", place=r"/\d{6}\.exr: decoding .* over the memory budget"))
    add(Case("limits/capture-resolution-huge",
             "generate {d}/s.lscene {d}/c.lcap -o {d}/out -q --memory-budget 1K".split(),
             names="frame", place="memory budget"))

    # --- 8. the residual layers of a generated collection -----------------------
    # lsds generate --compact writes the bundle, worldposition and motion in the
    # residual layouts, which decode from header attributes and another layer.
    generated = os.path.join(base, "G")
    if not os.path.isdir(generated):
        subprocess.run([lsds, "generate", "--demo", "--demo-size", "32x24",
                        "--demo-frames", "3", "--compact", "-o", generated, "-q"], check=True,
                       stdout=subprocess.DEVNULL)

    def add_generated(case, *setups):
        case.setup = [lambda d: shutil.copytree(generated, os.path.join(d, "C"),
                                                symlinks=True)] + list(setups)
        cases.append(case)

    def patch_attribute(path, key, change):
        # A header string attribute's value, changed in place (same length).
        data = bytearray(open(path, "rb").read())
        at = data.find(key + b"\x00string\x00")
        assert at >= 0, key
        value = at + len(key) + len(b"\x00string\x00") + 4
        size = int.from_bytes(data[value - 4:value], "little")
        data[value:value + size] = change(bytes(data[value:value + size]))
        write(path, bytes(data))

    residual_readers = {
        "bundle": {"validate": ("validate {d}/C", (1,)),
                   "bundles": ("bundles {d}/C -o {d}/stats.json", (2,))},
        "worldposition": {"validate": ("validate {d}/C", (1,)),
                          "export-layers": ("export-layers {d}/C -o {d}/out", (2,))},
        "motion": {"validate": ("validate {d}/C", (1,)),
                   "export-layers": ("export-layers {d}/C -o {d}/out", (2,))},
    }
    first_letter_x = lambda v: b"x" + v[1:]
    residual_mutations = [
        ("truncated", None, lambda p: write(p, open(p, "rb").read()[:300])),
        ("garbage", None, lambda p: write(p, b"v/1\x01" + bytes(range(256)) * 8)),
        ("layout-attribute", {"bundle": b"lsdsBundleLayout",
                              "worldposition": b"lsdsWorldPositionLayout",
                              "motion": b"lsdsMotionLayout"}, None),
        ("depth-attribute", {"worldposition": b"lsdsWorldPositionDepthLayer",
                             "motion": b"lsdsMotionDepthLayer"}, None),
        ("camera-attribute", {"motion": b"lsdsMotionPreviousCamera"}, None),
    ]
    for label, keys, mutate in residual_mutations:
        for layer, commands in residual_readers.items():
            if keys is not None and layer not in keys:
                continue
            path = lambda d, layer=layer: os.path.join(d, "C", layer, "000001.exr")
            if mutate is None:
                mutate_layer = (lambda d, key=keys[layer], path=path:
                                patch_attribute(path(d), key, first_letter_x))
            else:
                mutate_layer = lambda d, mutate=mutate, path=path: mutate(path(d))
            for command, (line, expect) in commands.items():
                add_generated(Case("residual/%s/%s/%s" % (label, layer, command),
                                   line.split(), expect=expect,
                                   names="%s/000001.exr" % layer), mutate_layer)
    # Another frame's motion: read against the wrong previous camera.
    for source in ("000000.exr", "000002.exr"):
        add_generated(Case("residual/motion-of-frame-%s/validate" % source[5],
                           "validate {d}/C".split(), expect=(1,),
                           names="motion/000001.exr", place="layer.motion-reference"),
                      lambda d, source=source: shutil.copyfile(
                          os.path.join(d, "C", "motion", source),
                          os.path.join(d, "C", "motion", "000001.exr")))
    return cases


def run_case(lsds, work, case):
    d = os.path.join(work, "cases", case.name.replace("/", "__"))
    if os.path.lexists(d):
        shutil.rmtree(d)
    os.makedirs(d)
    for setup in case.setup:
        setup(d)
    before = tree_state(d)
    argv = [lsds] + [a.replace("{d}", d) for a in case.args]
    env = dict(os.environ)
    env.update(case.env)
    env.pop("CI", None)
    env["LSDS_LOCK_TIMEOUT"] = "5"
    start = time.time()
    try:
        proc = subprocess.run(argv, stdin=subprocess.DEVNULL, capture_output=True,
                              timeout=TIME_LIMIT_S, env=env)
    except subprocess.TimeoutExpired:
        return "hang: no exit within %d s" % TIME_LIMIT_S, ""
    seconds = time.time() - start
    stderr = proc.stderr.decode("utf-8", "replace")
    # validate reports findings on stdout: the file is named there.
    said = stderr + proc.stdout.decode("utf-8", "replace")
    problems = []
    rc = proc.returncode
    if rc < 0 or rc >= 128:
        problems.append("crashed (exit %d)" % rc)
    elif rc not in case.expect:
        problems.append("exit %d, expected %s" % (rc, "/".join(map(str, case.expect))))
    for marker in ("AddressSanitizer", "LeakSanitizer", "runtime error:",
                   "UndefinedBehaviorSanitizer", "internal error"):
        if marker in stderr:
            problems.append("stderr has '%s'" % marker)
    if case.names and case.names not in said:
        problems.append("output does not name '%s'" % case.names)
    if case.place and not re.search(case.place, said):
        problems.append("stderr does not say the place /%s/" % case.place)
    after = tree_state(d)
    if after != before:
        changed = sorted(p for p in set(before) | set(after)
                         if before.get(p) != after.get(p))
        problems.append("files changed or added: " +
                        ", ".join(os.path.relpath(p, d) for p in changed[:5]))
    if not problems:
        shutil.rmtree(d, ignore_errors=True)
    return "; ".join(problems), stderr.strip().splitlines()[-1:] and stderr.strip().splitlines()[-1]


def corpus_main(doc, build, tools=0, run=run_case, prepare=None, finish=None):
    """The command line every corpus script shares:
        SCRIPT LSDS [TOOL...] WORK [--filter TEXT] [--list]
    `tools` paths stand between the lsds binary and WORK (the fixture writers a corpus builds its
    sources with). build(lsds, *tools, work) returns the cases; prepare(lsds, work), when given,
    runs once before them and returns a state, or a text that fails the run at once;
    run(lsds, work, case) runs one case (run_case); finish(state) returns the failures found after
    them (files outside the case folders that changed, ...). Returns the exit code."""
    argv = [a for a in sys.argv[1:]]
    filter_text = ""
    if "--filter" in argv:
        i = argv.index("--filter")
        filter_text = argv[i + 1]
        del argv[i:i + 2]
    listing = "--list" in argv
    argv = [a for a in argv if a != "--list"]
    if len(argv) < tools + 2:
        print(doc)
        return 2
    paths = [os.path.abspath(a) for a in argv[:tools + 2]]
    lsds, work = paths[0], paths[-1]
    os.makedirs(work, exist_ok=True)
    cases = [c for c in build(*paths) if filter_text in c.name]
    if listing:
        for c in cases:
            print(c.name)
        print("%d cases" % len(cases))
        return 0
    state = prepare(lsds, work) if prepare else None
    if isinstance(state, str):
        print("FAIL %s" % state)
        return 1
    failed = []
    for case in cases:
        problem, last = run(lsds, work, case)
        if problem:
            failed.append(case.name)
            print("FAIL %s: %s\n     %s" % (case.name, problem, last))
    for problem in (finish(state) if finish else []):
        failed.append(problem)
        print("FAIL %s" % problem)
    print("%d cases, %d failed" % (len(cases), len(failed)))
    return 1 if failed else 0


def main():
    return corpus_main(__doc__, build_cases)


if __name__ == "__main__":
    sys.exit(main())
