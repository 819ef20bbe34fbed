#!/usr/bin/env python3
"""The goldens of the masks (iouType segm) in tests/evaluate/mask_eval_golden_test.cc.

  make_mask_goldens.py --lsds BUILD/tools/lsds \
      --maker BUILD/tests/evaluate/evaluate_golden_collection --pycocotools DIR [--write-predictions]

As make_goldens.py, on the same golden collection, with COCOeval(iouType="segm"). The ground truth
masks are the compressed RLE that `lsds convert --to coco` writes. The prediction sets of
data/segm/ use every form COCO.loadRes and COCOeval accept: compressed RLE strings with and
without boxes, uncompressed RLE and polygons (both with boxes, as loadRes needs them then).
--write-predictions first (re)writes data/segm/*.json, deterministically (random.Random(4401)).
"""
import argparse
import json
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import make_goldens  # noqa: E402

DATA = os.path.join(HERE, "data", "segm")


def runs(mask):
    """Uncompressed COCO RLE counts of a 2D 0/1 array (column-major, background first)."""
    flat = mask.flatten(order="F")
    counts, value, run = [], 0, 0
    for pixel in flat:
        if pixel != value:
            counts.append(run)
            run, value = 0, pixel
        run += 1
    counts.append(run)
    return counts


def shifted(np, mask, dx, dy):
    out = np.zeros_like(mask)
    h, w = mask.shape
    ys, xs = np.nonzero(mask)
    ys, xs = ys + dy, xs + dx
    keep = (ys >= 0) & (ys < h) & (xs >= 0) & (xs < w)
    out[ys[keep], xs[keep]] = 1
    return out


def make_predictions(gt, mask_utils, np):
    rng = random.Random(4401)
    images = {i["id"]: i for i in gt["images"]}
    categories = [c["id"] for c in gt["categories"]]

    def decode(a):
        return mask_utils.decode(a["segmentation"]).astype(np.uint8)

    def compressed(mask):
        rle = mask_utils.encode(np.asfortranarray(mask))
        return {"size": [int(s) for s in rle["size"]], "counts": rle["counts"].decode("ascii")}

    def uncompressed(mask):
        return {"size": list(mask.shape), "counts": runs(mask)}

    def box(mask):
        return [float(v) for v in mask_utils.toBbox(mask_utils.encode(np.asfortranarray(mask)))]

    def moved(a, most):
        return shifted(np, decode(a), rng.randint(-most, most), rng.randint(-most, most))

    anns = gt["annotations"]
    sets = {}
    # Exact masks (compressed, as converted) with boxes: loadRes's box branch, area w * h.
    sets["perfect"] = [{"image_id": a["image_id"], "category_id": a["category_id"],
                        "segmentation": a["segmentation"], "bbox": a["bbox"],
                        "score": make_goldens.r2(rng.uniform(0.5, 1))} for a in anns]
    # Moved masks, compressed, no boxes: loadRes's mask branch, area of the mask.
    jittered = []
    for a in anns:
        if rng.random() < 0.1:
            continue
        other = categories[(categories.index(a["category_id"]) + 1) % len(categories)]
        jittered.append({"image_id": a["image_id"],
                         "category_id": other if rng.random() < 0.05 else a["category_id"],
                         "segmentation": compressed(moved(a, 3)),
                         "score": make_goldens.r2(rng.uniform(0.3, 1))})
        if rng.random() < 0.15:
            jittered.append({"image_id": a["image_id"], "category_id": a["category_id"],
                             "segmentation": compressed(moved(a, 6)),
                             "score": make_goldens.r2(rng.uniform(0.1, 0.6))})
    sets["jittered"] = jittered
    # Uncompressed RLE with boxes, nothing under 16 pixels.
    missing = []
    for a in anns:
        if max(a["bbox"][2], a["bbox"][3]) < 16:
            continue
        mask = moved(a, 1)
        missing.append({"image_id": a["image_id"], "category_id": a["category_id"],
                        "segmentation": uncompressed(mask), "bbox": box(mask),
                        "score": make_goldens.r2(rng.uniform(0.4, 1))})
    sets["missing_small"] = missing
    # Polygons (random quadrilaterals) with boxes, and more than maxDets in the first image.
    fps = []
    for a in anns:
        mask = moved(a, 1)
        fps.append({"image_id": a["image_id"], "category_id": a["category_id"],
                    "segmentation": compressed(mask), "bbox": box(mask),
                    "score": make_goldens.r2(rng.uniform(0.2, 1))})

    def polygon(image, category, low, high):
        cx, cy = rng.uniform(0, image["width"]), rng.uniform(0, image["height"])
        r = rng.uniform(2, 30)
        xy = []
        for k in range(4):
            xy += [make_goldens.r2(cx + r * [1, 0, -1, 0][k] + rng.uniform(-3, 3)),
                   make_goldens.r2(cy + r * [0, 1, 0, -1][k] + rng.uniform(-3, 3))]
        xs, ys = xy[0::2], xy[1::2]
        return {"image_id": image["id"], "category_id": category, "segmentation": [xy],
                "bbox": [min(xs), min(ys), max(xs) - min(xs), max(ys) - min(ys)],
                "score": make_goldens.r2(rng.uniform(low, high))}

    for image in gt["images"]:
        fps += [polygon(image, rng.choice(categories), 0, 1) for _ in range(5)]
    first = images[gt["images"][0]["id"]]
    fps += [polygon(first, categories[0], 0.01, 0.3) for _ in range(110)]
    sets["false_positives"] = fps
    # A crowd region (uncompressed RLE, as COCO writes crowds) around the first annotation,
    # and detections inside it.
    a = anns[0]
    image = images[a["image_id"]]
    region = make_goldens.crowd_regions(gt)[0]
    x, y, w, h = [int(round(v)) for v in region["bbox"]]
    crowd_mask = np.zeros((image["height"], image["width"]), dtype=np.uint8)
    crowd_mask[y:y + h, x:x + w] = 1
    region["segmentation"] = uncompressed(crowd_mask)
    region["area"] = int(crowd_mask.sum())
    region["bbox"] = [x, y, w, h]
    crowd = [{"image_id": b["image_id"], "category_id": b["category_id"],
              "segmentation": compressed(moved(b, 1)),
              "score": make_goldens.r2(rng.uniform(0.3, 1))} for b in anns]
    for k in range(6):
        piece = np.zeros_like(crowd_mask)
        piece[y + h // 4:y + h // 4 + max(1, h // 3), x + k * w // 8:x + k * w // 8 + max(1, w // 5)] = 1
        crowd.append({"image_id": region["image_id"], "category_id": region["category_id"],
                      "segmentation": compressed(piece), "score": make_goldens.r2(rng.uniform(0.5, 1))})
    sets["crowd"] = crowd
    return sets, [region]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--lsds", required=True)
    parser.add_argument("--maker", required=True)
    parser.add_argument("--pycocotools", required=True)
    parser.add_argument("--write-predictions", action="store_true")
    args = parser.parse_args()
    sys.path.insert(0, args.pycocotools)
    import numpy as np
    from pycocotools import mask as mask_utils
    gt = make_goldens.converted_ground_truth(args.lsds, args.maker)
    if args.write_predictions:
        os.makedirs(DATA, exist_ok=True)
        sets, crowd = make_predictions(gt, mask_utils, np)
        for name, entries in sets.items():
            make_goldens.write_list(os.path.join(DATA, name + ".json"), entries)
        make_goldens.write_list(os.path.join(DATA, "crowd_regions.json"), crowd)
    make_goldens.print_table(args.pycocotools, gt, DATA, "segm")

if __name__ == "__main__":
    main()
