#!/usr/bin/env python3
"""The goldens of tests/evaluate/coco_eval_golden_test.cc, from the reference COCO API.

  make_goldens.py --lsds BUILD/tools/lsds --maker BUILD/tests/evaluate/evaluate_golden_collection \
                  --pycocotools DIR [--write-predictions]

Writes the golden collection (golden_collection.h) with the maker, converts it with
`lsds convert --to coco --images none`, and runs pycocotools' COCOeval (iouType bbox) on every
prediction set of data/ (the `crowd` set with the crowd regions of data/crowd.json added to the
ground truth), printing the 12 stats of each as the C++ table of the test. DIR holds the
`pycocotools` package with its `_mask` extension built (the README.md of tests/evaluate says how).
--write-predictions first (re)writes data/*.json, deterministically, from the ground truth.
"""
import argparse
import json
import os
import random
import subprocess
import sys
import tempfile
import types

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data")
CASES = ["perfect", "jittered", "missing_small", "false_positives", "crowd"]


def r2(v):
    return round(v, 2)


def jitter(rng, box, sigma):
    x, y, w, h = box
    w2 = max(1.0, w * (1 + rng.gauss(0, sigma)))
    h2 = max(1.0, h * (1 + rng.gauss(0, sigma)))
    return [r2(x + rng.gauss(0, sigma) * w), r2(y + rng.gauss(0, sigma) * h), r2(w2), r2(h2)]


def det(ann, bbox, score, category=None):
    return {"image_id": ann["image_id"], "category_id": category or ann["category_id"],
            "bbox": bbox, "score": score}


def random_box(rng, image, categories):
    w = r2(rng.uniform(2, 60))
    h = r2(rng.uniform(2, 60))
    return {"image_id": image["id"], "category_id": rng.choice(categories),
            "bbox": [r2(rng.uniform(0, image["width"] - w)), r2(rng.uniform(0, image["height"] - h)),
                     w, h], "score": r2(rng.uniform(0, 1))}


def make_predictions(gt):
    rng = random.Random(44)
    anns = gt["annotations"]
    categories = [c["id"] for c in gt["categories"]]
    sets = {}
    sets["perfect"] = [det(a, list(a["bbox"]), r2(rng.uniform(0.5, 1))) for a in anns]
    jittered = []
    for a in anns:
        if rng.random() < 0.1:
            continue
        other = categories[(categories.index(a["category_id"]) + 1) % len(categories)]
        jittered.append(det(a, jitter(rng, a["bbox"], 0.1), r2(rng.uniform(0.3, 1)),
                            other if rng.random() < 0.05 else None))
        if rng.random() < 0.15:
            jittered.append(det(a, jitter(rng, a["bbox"], 0.2), r2(rng.uniform(0.1, 0.6))))
    sets["jittered"] = jittered
    sets["missing_small"] = [det(a, jitter(rng, a["bbox"], 0.03), r2(rng.uniform(0.4, 1)))
                             for a in anns if max(a["bbox"][2], a["bbox"][3]) >= 16]
    fps = [det(a, jitter(rng, a["bbox"], 0.05), r2(rng.uniform(0.2, 1))) for a in anns]
    for image in gt["images"]:
        fps += [random_box(rng, image, categories) for _ in range(5)]
    first = gt["images"][0]
    for _ in range(110):  # more than maxDets = 100 in one image and category
        box = random_box(rng, first, categories)
        box["category_id"] = categories[0]
        box["score"] = r2(rng.uniform(0.01, 0.3))
        fps.append(box)
    sets["false_positives"] = fps
    crowd = crowd_regions(gt)
    crowd_dets = [det(a, jitter(rng, a["bbox"], 0.05), r2(rng.uniform(0.3, 1))) for a in anns]
    for region in crowd:
        x, y, w, h = region["bbox"]
        for k in range(6):
            crowd_dets.append({"image_id": region["image_id"], "category_id": region["category_id"],
                               "bbox": [r2(x + k * w / 8), r2(y + h / 4), r2(w / 5), r2(h / 3)],
                               "score": r2(rng.uniform(0.5, 1))})
    sets["crowd"] = crowd_dets
    return sets, crowd


def crowd_regions(gt):
    """A crowd region around the first annotation of the first image, 10 px larger."""
    a = gt["annotations"][0]
    image = next(i for i in gt["images"] if i["id"] == a["image_id"])
    x, y, w, h = a["bbox"]
    x0, y0 = max(0, x - 10), max(0, y - 10)
    x1, y1 = min(image["width"], x + w + 10), min(image["height"], y + h + 10)
    bbox = [x0, y0, x1 - x0, y1 - y0]
    return [{"id": 1000000, "image_id": a["image_id"], "category_id": a["category_id"],
             "bbox": bbox, "area": bbox[2] * bbox[3], "iscrowd": 1}]


def write_list(path, entries):
    with open(path, "w") as f:
        f.write("[\n" + ",\n".join(json.dumps(e, separators=(",", ":")) for e in entries) + "\n]\n")


def import_pycocotools(pycocotools_dir):
    """pycocotools' COCO and COCOeval from cocoapi's PythonAPI folder, the evaluation code as
    published (bench/peers/coco_eval_files.py uses it too)."""
    sys.path.insert(0, pycocotools_dir)
    # coco.py imports matplotlib for showAnns only; cocoeval.py:378 uses np.float, which
    # numpy 1.24 removed (it was the builtin float).
    for name in ["matplotlib", "matplotlib.pyplot", "matplotlib.collections", "matplotlib.patches"]:
        module = types.ModuleType(name)
        module.PatchCollection = module.Polygon = None
        sys.modules.setdefault(name, module)
    import numpy as np
    if not hasattr(np, "float"):
        np.float = float
    from pycocotools.coco import COCO
    from pycocotools.cocoeval import COCOeval
    return COCO, COCOeval


def coco_stats(pycocotools_dir, gt, predictions, iou_type="bbox"):
    COCO, COCOeval = import_pycocotools(pycocotools_dir)
    coco = COCO()
    coco.dataset = gt
    coco.createIndex()
    results = coco.loadRes(predictions)
    e = COCOeval(coco, results, iou_type)
    e.evaluate()
    e.accumulate()
    e.summarize()
    return [float(s) for s in e.stats]


def converted_ground_truth(lsds, maker):
    """The golden collection written by the maker, as `lsds convert --to coco` writes it."""
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([maker, os.path.join(tmp, "c")], check=True)
        subprocess.run([lsds, "convert", os.path.join(tmp, "c"), "--to", "coco", "--images",
                        "none", "-q", "-o", os.path.join(tmp, "coco")], check=True)
        return json.load(open(os.path.join(tmp, "coco", "annotations", "instances_train.json")))


def print_table(pycocotools_dir, gt, data, iou_type):
    """COCOeval's stats of every case of `data` (crowd: with its crowd regions) as the C++ table."""
    table = []
    for name in CASES:
        predictions = json.load(open(os.path.join(data, name + ".json")))
        case_gt = json.loads(json.dumps(gt))
        if name == "crowd":
            case_gt["annotations"] += json.load(open(os.path.join(data, "crowd_regions.json")))
        table.append((name, coco_stats(pycocotools_dir, case_gt, predictions, iou_type)))
    for name, stats in table:
        print('    {"%s", {%s}},' % (name, ", ".join("%.17g" % s for s in stats)))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--lsds", required=True)
    parser.add_argument("--maker", required=True)
    parser.add_argument("--pycocotools", required=True)
    parser.add_argument("--write-predictions", action="store_true")
    args = parser.parse_args()
    gt = converted_ground_truth(args.lsds, args.maker)
    if args.write_predictions:
        sets, crowd = make_predictions(gt)
        for name, entries in sets.items():
            write_list(os.path.join(DATA, name + ".json"), entries)
        write_list(os.path.join(DATA, "crowd_regions.json"), crowd)
    print_table(args.pycocotools, gt, DATA, "bbox")


if __name__ == "__main__":
    main()
