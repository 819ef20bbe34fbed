#!/usr/bin/env python3
"""kill -9 at random moments during the commands that write (docs/reliability.md).

    kill9.py LSDS WORK [--repeats N] [--seed S]

For each of `generate`, `convert`, `bundles --write-layers`, `perturb-metadata` and
`backproject --fuse`, a reference run on a small collection times the command; then the
command is started N times and killed with SIGKILL after a random share of that time.
After every kill:
  - the inputs are byte-identical (sha256 of every file before and after), with nothing
    added to them but lsds temporaries (`.NAME.lsds-tmp-...`, swept by the next run);
  - what the command writes is either absent or complete: a collection folder without
    collection.json fails `lsds info` and `lsds validate`; collection.json is the old one
    or the new one, whole, and validates; a convert or backproject output is byte-identical
    to the reference run's;
  - running the command again completes to the reference run's result byte for byte
    (`generate --resume` for generate, `--force` where the command's own earlier output
    is present).
The random seed is printed, so a failing sequence of kill moments can be replayed.
"""
import argparse
import hashlib
import os
import random
import shutil
import signal
import subprocess
import sys
import time

TEMP_MARKER = ".lsds-tmp-"
FAILURES = []


def fail(message):
    FAILURES.append(message)
    print("FAIL: " + message, flush=True)


def tree_hashes(root):
    """{relative path: sha256} of every file below root; folders as entries too."""
    out = {}
    if not os.path.exists(root):
        return out
    if os.path.isfile(root):
        with open(root, "rb") as f:
            return {".": hashlib.sha256(f.read()).hexdigest()}
    for folder, dirs, files in os.walk(root):
        rel_folder = os.path.relpath(folder, root)
        for d in dirs:
            out[os.path.normpath(os.path.join(rel_folder, d)) + "/"] = "dir"
        for name in files:
            path = os.path.join(folder, name)
            with open(path, "rb") as f:
                out[os.path.normpath(os.path.join(rel_folder, name))] = hashlib.sha256(
                    f.read()).hexdigest()
    return out


def is_temp(rel):
    return any(TEMP_MARKER in part for part in rel.split("/"))


def run(cmd, timeout=120):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          timeout=timeout)


def must(cmd):
    r = run(cmd)
    if r.returncode != 0:
        raise SystemExit("setup failed: %s\n%s%s" % (" ".join(cmd), r.stdout, r.stderr))
    return r


def timed(cmd):
    start = time.monotonic()
    must(cmd)
    return time.monotonic() - start


def kill_after(cmd, delay):
    """Starts cmd, sends SIGKILL after `delay` seconds; True if it was still running."""
    process = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        process.wait(timeout=delay)
        return False
    except subprocess.TimeoutExpired:
        process.send_signal(signal.SIGKILL)
        process.wait()
        return True


def check_inputs(label, before, root, allowed_new=()):
    """Every file of `before` unchanged in root; new entries only temporaries or allowed."""
    after = tree_hashes(root)
    for rel, digest in before.items():
        if after.get(rel) != digest:
            fail("%s: input %s changed or vanished" % (label, os.path.join(root, rel)))
    for rel in after:
        if rel in before or is_temp(rel):
            continue
        if any(rel == a or rel.startswith(a.rstrip("/") + "/") for a in allowed_new):
            continue
        fail("%s: %s appeared inside the input" % (label, os.path.join(root, rel)))


def same_tree(label, got_root, want):
    got = {k: v for k, v in tree_hashes(got_root).items() if not is_temp(k)}
    if got != want:
        differing = sorted(set(got.items()) ^ set(want.items()))[:6]
        fail("%s: %s differs from the uninterrupted run: %s" % (label, got_root, differing))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("lsds")
    parser.add_argument("work")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seed", type=int, default=None)
    args = parser.parse_args()
    seed = args.seed if args.seed is not None else random.randrange(1 << 30)
    rng = random.Random(seed)
    print("kill9: seed %d (replay with --seed %d)" % (seed, seed), flush=True)
    lsds = os.path.abspath(args.lsds)
    work = os.path.abspath(args.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)

    def at(*parts):
        return os.path.join(work, *parts)

    def moment(duration):
        # Anywhere in the run, including its first and last instants.
        return rng.uniform(0.0, duration * 1.1)

    # --- generate: a small demo with a bundle layer (spp 4) for the bundles case.
    gen = [lsds, "generate", "--demo", "--demo-frames", "4", "--demo-size", "32x24", "--spp",
           "4", "--seed", "5", "-q"]
    duration = timed(gen + ["-o", at("ref")])
    reference = tree_hashes(at("ref"))
    killed = 0
    for r in range(args.repeats):
        out = at("gen%d" % r)
        killed += kill_after(gen + ["-o", out], moment(duration))
        if os.path.exists(os.path.join(out, "collection.json")):
            # collection.json is written last: present means complete.
            if run([lsds, "validate", out]).returncode != 0:
                fail("generate: killed run left a collection.json that does not validate")
            same_tree("generate (collection.json present after kill)", out, reference)
        elif os.path.exists(out):
            for command in ("info", "validate"):
                if run([lsds, command, out]).returncode == 0:
                    fail("generate: lsds %s accepts the half-written %s" % (command, out))
        resumed = run(gen + ["-o", out, "--resume"])
        if resumed.returncode != 0:
            fail("generate --resume after kill: exit %d: %s" % (resumed.returncode,
                                                               resumed.stderr.strip()))
        same_tree("generate --resume", out, reference)
    print("generate: %d of %d runs killed mid-way, reference %.2f s" % (killed, args.repeats,
                                                                     duration), flush=True)

    # --- commands whose outputs lie outside the collection, an input only.
    src = at("ref")

    def outside(name, cmd, suffix):
        duration = timed(cmd + ["-o", at(name + "_ref" + suffix)])
        done = tree_hashes(at(name + "_ref" + suffix))
        killed = 0
        for r in range(args.repeats):
            out = at("%s%d%s" % (name, r, suffix))
            killed += kill_after(cmd + ["-o", out], moment(duration))
            check_inputs(name, reference, src)
            if os.path.exists(out):
                same_tree("%s (output present after kill)" % name, out, done)
            rerun = run(cmd + ["-o", out, "--force"])
            if rerun.returncode != 0:
                fail("%s rerun after kill: %s" % (name, rerun.stderr.strip()))
            same_tree("%s rerun" % name, out, done)
        print("%s: %d of %d runs killed mid-way, reference %.2f s" % (name, killed, args.repeats,
                                                                     duration), flush=True)

    outside("convert", [lsds, "convert", src, "--to", "coco", "--images", "png"], "")
    outside("backproject", [lsds, "backproject", src, "--fuse", "--voxel", "0.5"], ".ply")

    # --- commands that write into the collection: old or new collection.json, whole.
    def in_place(name, args_tail, outputs):
        base = at(name + "_ref")
        shutil.copytree(src, base)
        cmd = [lsds] + args_tail
        duration = timed([a.replace("COLLECTION", base) for a in cmd])
        done = tree_hashes(base)
        old_json = reference["collection.json"]
        new_json = done["collection.json"]
        killed = 0
        for r in range(args.repeats):
            target = at("%s%d" % (name, r))
            shutil.copytree(src, target)
            this = [a.replace("COLLECTION", target) for a in cmd]
            killed += kill_after(this, moment(duration))
            kept = {k: v for k, v in reference.items() if k != "collection.json"}
            check_inputs(name, kept, target, allowed_new=("collection.json",) + tuple(outputs))
            now = tree_hashes(target).get("collection.json")
            if now not in (old_json, new_json):
                fail("%s: collection.json after kill is neither the old nor the new one" % name)
            if run([lsds, "validate", target]).returncode != 0:
                fail("%s: the collection does not validate after the kill" % name)
            if now == new_json:  # registered: the outputs must be complete
                same_tree("%s (registered after kill)" % name, target, done)
            rerun = run(this + ["--force"])
            if rerun.returncode != 0:
                fail("%s rerun after kill: %s" % (name, rerun.stderr.strip()))
            same_tree("%s rerun" % name, target, done)
        print("%s: %d of %d runs killed mid-way, reference %.2f s" % (name, killed, args.repeats,
                                                                     duration), flush=True)

    in_place("bundles", ["bundles", "COLLECTION", "--write-layers", "majority,purity,edge"],
             ("majority/", "purity/", "edge/"))
    in_place("perturb", ["perturb-metadata", "COLLECTION", "--seed", "3", "--sigma", "0.5,0.2"],
             ("metadata.perturbed-3.json",))

    if FAILURES:
        print("kill9: %d failure(s) (seed %d)" % (len(FAILURES), seed))
        return 1
    print("kill9: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
