#!/usr/bin/env python3
"""Hostile prediction files of lsds evaluate (docs/reliability.md, docs/evaluate.md).

The same rules as hostile_corpus.py, whose machinery this reuses: each case
exits 2 naming the file (and, where the case says so, the line or the JSON
pointer), within the time limit, with no crash, and leaves every file of its
folder byte-identical (no evaluation written). One valid prediction set per
reader (a COCO results file with boxes, one with masks, a YOLO txt folder, a
DOTA task-1 folder, a MOT tracker folder), each broken in the ways the other
readers' corpora break their inputs: NaN, numbers beyond double, truncated,
NUL bytes, a sparse 1 GiB file, garbage bytes, a FIFO, deep JSON nesting.

usage: evaluate_corpus.py LSDS WORK [--filter SUBSTRING] [--list]
"""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_corpus import DEEP, Case, corpus_main, fifo, write  # noqa: E402

GIB = 1 << 30

# Valid predictions for the corpus' synthetic collection (lsds synth --count 2
# --size 32x24: classes box and crate; frames 0 and 1).
COCO = (b'[{"image_id": 1, "category_id": 1, "bbox": [10, 10, 3, 4], "score": 0.9},\n'
        b' {"image_id": 2, "category_id": 2, "bbox": [14, 13, 4, 4], "score": 0.8}]\n')
# A mask result: a 32x24 image, RLE counts of 10 background then 5 object pixels.
SEGM = (b'[{"image_id": 1, "category_id": 1, "segmentation": {"size": [24, 32], '
        b'"counts": "1:5"}, "score": 0.9}]\n')
# A segment model's polygons (class, x y pairs, confidence).
YOLO_SEG = b"0 0.3 0.4 0.4 0.4 0.4 0.6 0.3 0.6 0.9\n1 0.2 0.6 0.3 0.6 0.3 0.7 0.8\n"
YOLO = b"0 0.359375 0.5 0.09375 0.166667 0.9\n1 0.234375 0.625 0.15625 0.166667 0.8\n"
DOTA = b"000000 0.9 10 10 13 10 13 14 10 14\n000001 0.8 19 10 22 10 22 14 19 14\n"
MOT = b"1,1,11,11,3,4,0.9,-1,-1,-1\n2,1,20,11,3,4,0.8,-1,-1,-1\n"


def sparse(path, size=GIB):
    """A file of `size` zero bytes that takes no disk (a hole)."""
    if os.path.lexists(path):
        os.remove(path)
    with open(path, "wb") as f:
        f.truncate(size)


def text_mutations(valid, number):
    """(label, bytes or None for a sparse file, place regex) for a text file of lines;
    `number` is a value of the first line to break."""
    return [
        ("nan", valid.replace(number, b"nan", 1), r":1\b"),
        ("beyond-double", valid.replace(number, b"1e999", 1), r":1\b"),
        ("truncated", valid[: valid.index(b"\n") // 2] + b"\n", r":1\b"),
        ("nul-bytes", valid[:5] + b"\0\0" + valid[5:], r":1:\d+"),
        ("garbage", bytes(range(256)) * 4, None),
        ("sparse-1gib", None, None),
    ]


def json_mutations(valid, number):
    return [
        ("empty", b"", None),
        ("nan", valid.replace(number, b"NaN", 1), r"#/0/"),
        ("beyond-double", valid.replace(number, b"1e99999", 1), None),
        ("truncated", valid[: len(valid) // 2], r":\d+:\d+"),
        ("nul-bytes", valid[:40] + b"\0\0\0" + valid[40:], r":\d+:\d+"),
        ("deep-arrays", b"[" * DEEP + b"]" * DEEP, "nesting deeper"),
        ("deep-in-entry", valid.replace(b'"score"', b'"x": ' + b"[" * DEEP + b"]" * DEEP
                                        + b', "score"', 1), "nesting deeper"),
        ("sparse-1gib", None, None),
    ]


def build_cases(lsds, work):
    base = os.path.join(work, "base")
    collection = os.path.join(base, "C")
    if not os.path.isdir(collection):
        os.makedirs(base, exist_ok=True)
        subprocess.run([lsds, "synth", collection, "--count", "2", "--size", "32x24",
                        "--samples-per-axis", "2"], check=True, stdout=subprocess.DEVNULL)
    cases = []

    def add(case, setup):
        def copy_collection(d):
            shutil.copytree(collection, os.path.join(d, "C"), symlinks=True)
        case.setup = [copy_collection, setup]
        cases.append(case)

    def put(path, data):
        if data is None:
            os.makedirs(os.path.dirname(path), exist_ok=True)
            sparse(path)
        else:
            write(path, data)

    out = "-o {d}/e.json"
    readers = [
        # (name, file under the case folder, command, valid bytes, number to break, json?)
        ("coco", "p.json", "evaluate {d}/C --predictions {d}/p.json " + out, COCO, b"0.9", True),
        ("coco-segm", "p.json",
         "evaluate {d}/C --iou-type segm --predictions {d}/p.json " + out, SEGM, b"0.9", True),
        ("yolo", "Y/000000.txt",
         "evaluate {d}/C --format yolo --predictions {d}/Y " + out, YOLO, b"0.359375", False),
        ("yolo-seg", "Y/000000.txt",
         "evaluate {d}/C --format yolo --iou-type segm --predictions {d}/Y " + out, YOLO_SEG,
         b"0.3", False),
        ("dota", "D/Task1_box.txt",
         "evaluate {d}/C --format dota --iou-type obb --predictions {d}/D " + out, DOTA, b"13",
         False),
        ("mot", "M/S1-shot0.txt",
         "evaluate {d}/C --classes box --format mot --predictions {d}/M " + out, MOT, b"0.9",
         False),
    ]
    for name, relative, line, valid, number, is_json in readers:
        mutations = json_mutations(valid, number) if is_json else text_mutations(valid, number)
        for label, data, place in mutations:
            add(Case("%s/%s" % (name, label), line.split(), names=os.path.basename(relative),
                     place=place),
                lambda d, relative=relative, data=data: put(os.path.join(d, relative), data))
        add(Case("%s/fifo" % name, line.split(), names=os.path.basename(relative)),
            lambda d, relative=relative: (os.makedirs(os.path.dirname(os.path.join(d, relative)),
                                                      exist_ok=True),
                                          fifo(os.path.join(d, relative))))

    # Masks the COCO API would read out of bounds or never finish decoding.
    segm_line = ("evaluate {d}/C --iou-type segm --predictions {d}/p.json " + out).split()
    bad_masks = [
        ("rle-bad-character", SEGM.replace(b"1:5", b"1:5\x7f"), r"#/0/segmentation"),
        ("rle-longer-than-image", SEGM.replace(b"1:5", b"1:" + b"o" * 12 + b"0"),
         r"#/0/segmentation"),
        ("rle-size-not-image", SEGM.replace(b"[24, 32]", b"[2400000000, 3200000000]"),
         r"#/0/segmentation"),
        ("polygon-nan", SEGM.replace(b'{"size": [24, 32], "counts": "1:5"}',
                                     b"[[1, 1, NaN, 1, 4, 4]]"), r"#/0/segmentation"),
        ("polygon-huge", SEGM.replace(b'{"size": [24, 32], "counts": "1:5"}',
                                      b"[[1, 1, 1e300, 1, 4, 4]]"), r"#/0/segmentation"),
    ]
    for label, data, place in bad_masks:
        add(Case("coco-segm/" + label, segm_line, names="p.json", place=place),
            lambda d, data=data: write(os.path.join(d, "p.json"), data))

    # Tracker rows of a class the ground truth (box, crate) does not have (0
    # stands for the one class only when there is one).
    mot_line = ("evaluate {d}/C --format mot --predictions {d}/M " + out).split()
    bad_classes = [
        ("class-unknown", b"1,1,11,11,3,4,0.9,7\n", r":1\b"),
        ("class-beyond-int", b"1,1,11,11,3,4,0.9,1e300\n", r":1\b"),
        ("class-zero-two-categories", b"1,1,11,11,3,4,0.9,0\n", r":1\b"),
    ]
    for label, data, place in bad_classes:
        add(Case("mot/" + label, mot_line, names="S1-shot0.txt", place=place),
            lambda d, data=data: write(os.path.join(d, "M", "S1-shot0.txt"), data))

    # Polygons Ultralytics' polygon2mask would cast out of int32, or lines that
    # are not class, pairs and a confidence.
    seg_line = ("evaluate {d}/C --format yolo --iou-type segm --predictions {d}/Y " + out).split()
    bad_polygons = [
        ("polygon-huge", YOLO_SEG.replace(b"0.4 0.4", b"1e300 0.4", 1), r":1\b"),
        ("polygon-no-confidence", b"0 0.3 0.4 0.4 0.4 0.4 0.6 0.3 0.6\n", r":1\b"),
        ("polygon-two-points", b"0 0.3 0.4 0.4 0.4 0.9\n", r":1\b"),
    ]
    for label, data, place in bad_polygons:
        add(Case("yolo-seg/" + label, seg_line, names="000000.txt", place=place),
            lambda d, data=data: write(os.path.join(d, "Y", "000000.txt"), data))
    return cases


def main():
    return corpus_main(__doc__, build_cases)


if __name__ == "__main__":
    sys.exit(main())
