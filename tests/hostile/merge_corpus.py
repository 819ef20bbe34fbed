#!/usr/bin/env python3
"""Hostile inputs of lsds merge, submit and perturb-metadata (docs/reliability.md).

The same rules as hostile_corpus.py, whose machinery this reuses: each case
exits 2 naming the file and the place, within the time limit, with no crash,
and leaves every file of its folder byte-identical (no partial output, inputs
untouched). Files outside the case folder that a case points at (a symlink's
target) are a FIFO or a file whose sha256 is checked too: reading the FIFO
would hang the case, so "nothing read from outside" is tested, not assumed.

usage: merge_corpus.py LSDS WORK [--filter SUBSTRING] [--list]
"""
import hashlib
import os
import shutil
import stat
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_corpus import Case, corpus_main, fifo, write  # noqa: E402

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples")


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def build_cases(lsds, work):
    base = os.path.join(work, "base")
    os.makedirs(base, exist_ok=True)

    def make(name, argv):
        path = os.path.join(base, name)
        if not os.path.isdir(path):
            subprocess.run([lsds] + argv + ["-o", path], check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                           env=dict(os.environ, CI="true"))
        return path

    demo = ["generate", "--demo", "--demo-frames", "4", "--spp", "1", "-q"]
    # Two shards of one demo run, and shard 1 of a demo of another size.
    shards = {
        "D0": make("D0", demo + ["--demo-size", "32x24", "--shard", "0/2"]),
        "D1": make("D1", demo + ["--demo-size", "32x24", "--shard", "1/2"]),
        "E1": make("E1", demo + ["--demo-size", "40x24", "--shard", "1/2"]),
    }
    collection = os.path.join(base, "C")
    if not os.path.isdir(collection):
        subprocess.run([lsds, "synth", collection, "--count", "2", "--size", "32x24",
                        "--samples-per-axis", "2"], check=True, stdout=subprocess.DEVNULL)

    # Outside every case folder: what hostile shards link to.
    outside = os.path.join(work, "outside")
    os.makedirs(outside, exist_ok=True)
    secret = os.path.join(outside, "secret.txt")
    write(secret, "not a layer\n")
    outside_fifo = os.path.join(outside, "fifo")
    if not os.path.exists(outside_fifo):
        os.mkfifo(outside_fifo)

    cases = []

    def copy_shards(*names):
        def setup(d):
            for name in names:
                shutil.copytree(shards[name], os.path.join(d, name), symlinks=True)
        return setup

    def add(case, *setups):
        case.setup = list(setups)
        cases.append(case)

    def relink(path, target):
        os.remove(path)
        os.symlink(target, path)

    merge = "merge {d}/D0 {d}/D1 -o {d}/out".split()

    # --- merge: what a shard holds instead of its layer files ---------------------
    layer = "D1/depth/000001.exr"
    add(Case("merge/layer-symlink-to-passwd", merge, names=layer,
             place="the layer file is a symbolic link \\(to /etc/passwd\\)"),
        copy_shards("D0", "D1"),
        lambda d: relink(os.path.join(d, layer), "/etc/passwd"))
    add(Case("merge/layer-symlink-to-outside-fifo", merge, names=layer,
             place="the layer file is a symbolic link"),
        copy_shards("D0", "D1"),
        lambda d: relink(os.path.join(d, layer), outside_fifo))
    add(Case("merge/layer-symlink-inside-shard", merge, names=layer,
             place="the layer file is a symbolic link"),
        copy_shards("D0", "D1"),
        lambda d: relink(os.path.join(d, layer), "../rgb/000001.exr"))
    add(Case("merge/layer-folder-symlink-outside", merge, names="D1/normal/000001.exr",
             place="its folder .*D1/normal is a symbolic link"),
        copy_shards("D0", "D1"),
        lambda d: (shutil.rmtree(os.path.join(d, "D1", "normal")),
                   os.symlink(outside, os.path.join(d, "D1", "normal"))))
    add(Case("merge/layer-fifo", merge, names="D1/rgb/000003.exr",
             place="the layer file is a FIFO"),
        copy_shards("D0", "D1"),
        lambda d: fifo(os.path.join(d, "D1", "rgb", "000003.exr")))
    add(Case("merge/layer-folder", merge, names="D1/shadow/000003.exr",
             place="the layer file is a folder"),
        copy_shards("D0", "D1"),
        lambda d: (os.remove(os.path.join(d, "D1", "shadow", "000003.exr")),
                   os.mkdir(os.path.join(d, "D1", "shadow", "000003.exr"))))

    def cut(path, keep):
        data = open(path, "rb").read()
        write(path, data[:keep(len(data))])

    add(Case("merge/layer-truncated-tail", merge, names=layer + " frame 1",
             place="layer 'depth': truncated"),
        copy_shards("D0", "D1"),
        lambda d: cut(os.path.join(d, layer), lambda n: n - 100))
    add(Case("merge/layer-truncated-half", merge, names=layer + " frame 1",
             place="layer 'depth': truncated"),
        copy_shards("D0", "D1"),
        lambda d: cut(os.path.join(d, layer), lambda n: n // 2))
    add(Case("merge/layer-truncated-header", merge, names=layer + " frame 1",
             place="layer 'depth': (malformed EXR header|cannot read)"),
        copy_shards("D0", "D1"),
        lambda d: cut(os.path.join(d, layer), lambda n: 60))
    add(Case("merge/layer-of-another-layer", merge, names=layer + " frame 1",
             place="layer 'depth': the file has no channel 'Z'"),
        copy_shards("D0", "D1"),
        lambda d: shutil.copyfile(os.path.join(d, "D1", "rgb", "000001.exr"),
                                  os.path.join(d, layer)))
    add(Case("merge/layer-of-another-size", merge, names=layer + " frame 1",
             place="layer 'depth': the file is 40x24 but the frame's camera is 32x24"),
        copy_shards("D0", "D1", "E1"),
        lambda d: shutil.copyfile(os.path.join(d, "E1", "depth", "000001.exr"),
                                  os.path.join(d, layer)))

    # --- merge: shards of two runs -------------------------------------------------
    add(Case("merge/demos-of-two-sizes", "merge {d}/D0 {d}/E1 -o {d}/out".split(),
             names="E1/collection.json",
             place="#/provenance/scene_source: not a shard of the same run.*40x24"),
        copy_shards("D0", "E1"))

    # --- merge: a full disk names the output -----------------------------------------
    for budget in ("0", "4000", "60000"):
        add(Case("merge/full-disk-after-%s-bytes" % budget, merge, names="/out/",
                 place=r"/out/\S+: cannot write.*No space left on device",
                 env={"LSDS_FAULT_WRITE_BYTES": budget}),
            copy_shards("D0", "D1"))

    # --- submit: every value the cluster gets is checked first ------------------------
    def scene_files(d):
        shutil.copyfile(os.path.join(EXAMPLES, "uav_survey.lscene"), os.path.join(d, "s.lscene"))
        shutil.copyfile(os.path.join(EXAMPLES, "demo_survey.lcap"), os.path.join(d, "c.lcap"))

    submit = "submit slurm {d}/s.lscene {d}/c.lcap --shards 2 -o {d}/run".split()
    for name, extra, flag, place in [
            ("depth-sideways", ["--depth", "sideways"], "--depth", "expected planar or perspective"),
            ("spp-3", ["--spp", "3"], "--spp 3", "must be a square number"),
            ("spp-negative", ["--spp=-4"], "--spp -4", "must be a square number"),
            ("mem-carriage-return", ["--mem", "8G\r"], "--mem '8G\\x0D'", "control characters"),
            ("time-carriage-return", ["--time", "1:00:00\r"], "--time", "control characters"),
            ("partition-newline", ["--partition", "cpu\nhostile"], "--partition",
             "control characters"),
            ("account-escape", ["--account", "a\x1b[2Jb"], "--account", "control characters"),
            ("job-name-tab", ["--job-name", "x\ty"], "--job-name", "control characters")]:
        add(Case("submit/" + name, submit + extra, names=flag, place=place), scene_files)

    # --- perturb-metadata: a report that cannot be written ------------------------------
    def copy_collection(d):
        shutil.copytree(collection, os.path.join(d, "C"), symlinks=True)

    perturb = "perturb-metadata {d}/C --sigma 1 --seed 3 --report".split()
    add(Case("perturb/report-is-a-folder", perturb[:-1] + ["--force", "--report={d}/taken"],
             names="taken", place="the report is a folder"),
        copy_collection, lambda d: os.makedirs(os.path.join(d, "taken", "inside")))
    for budget in ("0", "1500", "3000"):
        add(Case("perturb/full-disk-after-%s-bytes" % budget, perturb, names="/C/",
                 place=r"/C/\S+: cannot write.*No space left on device",
                 env={"LSDS_FAULT_WRITE_BYTES": budget}),
            copy_collection)
    return cases, [secret], outside_fifo


def main():
    outside = {}

    def build(lsds, work):
        cases, outside["files"], outside["fifo"] = build_cases(lsds, work)
        return cases

    def prepare(lsds, work):
        return {p: sha256(p) for p in outside["files"] + ["/etc/passwd"]}

    # Nothing outside the case folders was written to (or replaced).
    def finish(before):
        changed = ["%s changed" % p for p, digest in before.items() if sha256(p) != digest]
        if not stat.S_ISFIFO(os.lstat(outside["fifo"]).st_mode):
            changed.append("%s is no longer a FIFO" % outside["fifo"])
        return changed

    return corpus_main(__doc__, build, prepare=prepare, finish=finish)



if __name__ == "__main__":
    sys.exit(main())
