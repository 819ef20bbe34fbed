#!/usr/bin/env python3
"""The goldens of the oriented boxes (--iou-type obb) in tests/evaluate/dota_eval_golden_test.cc.

  make_obb_goldens.py --lsds BUILD/tools/lsds \
      --maker BUILD/tests/evaluate/evaluate_golden_collection --devkit DIR [--write-predictions]

Writes the golden collection with the maker, converts it with `lsds convert --to dota --images
none`, and runs the DOTA devkit's own task-1 evaluation (dota_evaluation_task1.py voc_eval, with
its polyiou SWIG extension built in DIR) on every prediction set of data/obb/, for VOC07 (the
devkit's main) and VOC10-12 AP, printing per-class APs and the mean as the C++ table of the test.
--write-predictions first (re)writes data/obb/<set>/Task1_<class>.txt, deterministically
(random.Random(4402)), every score distinct (the devkit's argsort is not stable).
"""
import argparse
import contextlib
import io
import math
import os
import random
import subprocess
import sys
import tempfile
import types

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data", "obb")
CASES = ["perfect", "jittered", "missing_small", "false_positives"]


def read_labels(folder):
    labels = {}
    for name in sorted(os.listdir(folder)):
        objects = []
        for line in open(os.path.join(folder, name)):
            t = line.strip().split(" ")
            if len(t) < 9:
                continue
            objects.append(([float(v) for v in t[:8]], t[8], t[9] if len(t) > 9 else "0"))
        labels[name[:-4]] = objects
    return labels


def transformed(quad, angle, dx, dy, scale):
    cx, cy = sum(quad[0::2]) / 4, sum(quad[1::2]) / 4
    c, s = math.cos(angle), math.sin(angle)
    out = []
    for i in range(4):
        x, y = (quad[2 * i] - cx) * scale, (quad[2 * i + 1] - cy) * scale
        out += [round(cx + dx + c * x - s * y, 2), round(cy + dy + s * x + c * y, 2)]
    return out


def longer_side(quad):
    return max(math.dist(quad[0:2], quad[2:4]), math.dist(quad[2:4], quad[4:6]))


def make_predictions(labels, classes):
    rng = random.Random(4402)
    scores = iter(rng.sample(range(1, 1000000), 100000))

    def score():
        return next(scores) / 1000000

    sets = {name: [] for name in CASES}
    for image, objects in labels.items():
        for quad, name, _ in objects:
            sets["perfect"].append((name, image, score(), quad))
            if rng.random() >= 0.1:
                side = longer_side(quad)
                sets["jittered"].append((name, image, score(), transformed(
                    quad, rng.gauss(0, 0.15), rng.gauss(0, 0.1) * side, rng.gauss(0, 0.1) * side,
                    1 + rng.gauss(0, 0.1))))
                if rng.random() < 0.15:
                    sets["jittered"].append((name, image, score(), transformed(
                        quad, rng.gauss(0, 0.3), rng.gauss(0, 0.2) * side,
                        rng.gauss(0, 0.2) * side, 1)))
            if longer_side(quad) >= 16:
                sets["missing_small"].append((name, image, score(), transformed(
                    quad, rng.gauss(0, 0.05), 0.5, -0.5, 1)))
            sets["false_positives"].append((name, image, score(), transformed(
                quad, rng.gauss(0, 0.05), 1, 1, 1)))
        for _ in range(5):
            cx, cy, r = rng.uniform(0, 256), rng.uniform(0, 192), rng.uniform(2, 30)
            quad = transformed([cx - r, cy - r / 2, cx + r, cy - r / 2, cx + r, cy + r / 2,
                                cx - r, cy + r / 2], rng.uniform(0, math.pi), 0, 0, 1)
            sets["false_positives"].append((rng.choice(classes), image, score(), quad))
    return sets


def write_sets(sets, classes):
    for case, entries in sets.items():
        folder = os.path.join(DATA, case)
        os.makedirs(folder, exist_ok=True)
        for name in classes:
            with open(os.path.join(folder, "Task1_%s.txt" % name), "w") as f:
                for n, image, s, quad in entries:
                    if n == name:
                        f.write("%s %s %s\n" % (image, repr(s), " ".join(repr(v) for v in quad)))


def devkit_aps(devkit, label_folder, images, classes, case, use_07):
    sys.path.insert(0, devkit)
    for name in ["matplotlib", "matplotlib.pyplot"]:
        sys.modules.setdefault(name, types.ModuleType(name))
    import numpy as np
    if not hasattr(np, "bool"):
        np.bool = bool  # task1.py:151 uses the alias numpy 1.24 removed (the builtin bool)
    import dota_evaluation_task1 as task1
    with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
        f.write("\n".join(images) + "\n")
        imageset = f.name
    aps = []
    for name in classes:
        with contextlib.redirect_stdout(io.StringIO()):
            _, _, ap = task1.voc_eval(os.path.join(DATA, case, "Task1_{:s}.txt"),
                                      os.path.join(label_folder, "{:s}.txt"), imageset, name,
                                      ovthresh=0.5, use_07_metric=use_07)
        aps.append(float(ap))
    os.unlink(imageset)
    return aps


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--lsds", required=True)
    parser.add_argument("--maker", required=True)
    parser.add_argument("--devkit", required=True)
    parser.add_argument("--write-predictions", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([args.maker, os.path.join(tmp, "c")], check=True)
        subprocess.run([args.lsds, "convert", os.path.join(tmp, "c"), "--to", "dota", "--images",
                        "none", "-q", "-o", os.path.join(tmp, "dota")], check=True)
        classes = open(os.path.join(tmp, "dota", "dota_classes.txt")).read().split()
        label_folder = os.path.join(tmp, "dota", "labelTxt", "train")
        labels = read_labels(label_folder)
        if args.write_predictions:
            write_sets(make_predictions(labels, classes), classes)
        for case in CASES:
            for use_07 in (True, False):
                aps = devkit_aps(args.devkit, label_folder, sorted(labels), classes, case, use_07)
                kept = [a for a in aps if not math.isnan(a)]
                print('    {"%s", VocAp::%s, {%s}, %.17g},' % (
                    case, "k07" if use_07 else "k12", ", ".join("%.17g" % a for a in aps),
                    sum(kept) / len(kept)))


if __name__ == "__main__":
    main()
