#!/usr/bin/env python3
"""The decoders' part of the malformed-input corpus (docs/reliability.md).

Hostile PNG, PFM, EXR and .npy files in the sources of `lsds import`, NUL
bytes and sparse gigabyte files in every JSON input, run through the CLI with
the machinery of hostile_corpus.py: every case must exit 2, name the file
and the place, finish within the time limit, not crash, and leave every file
of its folder byte-identical with none added.

The importers' sources are the fixtures of tests/import, written once by the
write_import_fixture binary (tests/import); each case copies one and breaks one kind of file.

usage: decoder_corpus.py LSDS DECODER_FIXTURES WORK [--filter SUBSTRING] [--list]
"""
import glob
import os
import shutil
import struct
import subprocess
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_corpus import Case, corpus_main, write  # noqa: E402

FORMATS = ("ue-mrq", "airsim", "bop", "kubric", "replicator", "solo")
DEEP = 100000
GIB = 1 << 30


# --- crafted files ---------------------------------------------------------------

def png(width, height, bit_depth, colour_type, pixels=b"", palette=None):
    """A PNG whose IHDR declares width x height; `pixels` deflated as its IDAT."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))
    out = b"\x89PNG\r\n\x1a\n"
    out += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bit_depth,
                                      colour_type, 0, 0, 0))
    if palette is not None:
        out += chunk(b"PLTE", palette)
    out += chunk(b"IDAT", zlib.compress(pixels, 9))
    out += chunk(b"IEND", b"")
    return out


# 10^6 x 10^6 RGB: OpenCV's size assertion escaped as an internal error.
PNG_HUGE = png(10 ** 6, 10 ** 6, 8, 2, b"\0" * 64)
# Within the readers' side limit, but 2.7 GB of pixels in 100 bytes.
PNG_DENSE = png(30000, 30000, 8, 2, b"\0" * 64)
# An indexed PNG of 40000 x 40000 in about 100 bytes: libpng sized it (1.6 GB).
PNG_PALETTE_BOMB = png(40000, 40000, 8, 3, b"\0" * 64, palette=b"\0\0\0\xff\xff\xff")
# 18 bytes declaring 32768 x 32768 floats (4.3 GB allocated before reading).
PFM_HUGE = b"Pf\n32768 32768\n-1\n"
# An EXR attribute declaring 2 GB in a file of a hundred bytes.
EXR_BOMB = (struct.pack("<II", 20000630, 2) + b"comments\0string\0"
            + struct.pack("<I", 0x7ff00000) + b"x" * 64)


def npy(header):
    """A version 2.0 .npy file (4-byte header length) with `header` and no data."""
    text = header.encode() + b"\n"
    return b"\x93NUMPY\x02\x00" + struct.pack("<I", len(text)) + text


NPY_NESTED = npy("{'descr': '<f4', 'fortran_order': False, 'shape': "
                 + "(" * DEEP + "1" + ",)" * DEEP + ", }")
NPY_FIELD_NESTED = npy("{'descr': [('x', '<f4', " + "(" * DEEP + "2" + ",)" * DEEP
                       + ")], 'fortran_order': False, 'shape': (1,), }")
# 2^32 x 2^32 wraps to 0 bytes in 64 bits: the empty payload "matched".
NPY_SHAPE_OVERFLOW = npy("{'descr': '<f4', 'fortran_order': False, "
                         "'shape': (4294967296, 4294967296), }")


def sparse(path, size=GIB):
    """A file of `size` zero bytes that takes no disk (a hole)."""
    if os.path.lexists(path):
        os.remove(path)
    with open(path, "wb") as f:
        f.truncate(size)


def replace_all(root, pattern, data):
    paths = sorted(glob.glob(os.path.join(root, "**", pattern), recursive=True))
    assert paths, "no %s under %s" % (pattern, root)
    for p in paths:
        write(p, data(p) if callable(data) else data)


def sparse_all(root, pattern):
    paths = sorted(glob.glob(os.path.join(root, "**", pattern), recursive=True))
    assert paths, "no %s under %s" % (pattern, root)
    for p in paths:
        sparse(p)


def with_nul(p):
    """The file's own bytes, then a NUL and more text: nlohmann stopped at the
    NUL and took the document before it for all of it."""
    return open(p, "rb").read() + b"\0{\"ignored\": true}"


NUL_PLACE = r":\d+:\d+: a NUL byte"


# --- the cases ---------------------------------------------------------------------

def build_cases(lsds, fixtures, work):
    cases = []
    base = os.path.join(work, "base")
    os.makedirs(base, exist_ok=True)

    # One source per importer, written once; `sources[f]` is the folder to
    # import, relative to the copy the case makes.
    sources = {}
    for fmt in FORMATS:
        folder = os.path.join(base, fmt)
        marker = folder + ".source"
        if not os.path.exists(marker):
            if os.path.isdir(folder):
                shutil.rmtree(folder)
            out = subprocess.run([fixtures, fmt, folder], check=True,
                                 capture_output=True, text=True).stdout.strip()
            write(marker, os.path.relpath(out, folder))
        sources[fmt] = open(marker).read().strip()

    def add_import(name, fmt, mutate, names, place, expect=(2,)):
        source = sources[fmt]
        args = ["import", fmt, "{d}/S/" + source, "-o", "{d}/out"]
        case = Case("import/%s/%s" % (name, fmt), args, expect=expect, names=names,
                    place=place)
        case.setup = [lambda d, fmt=fmt: shutil.copytree(os.path.join(base, fmt),
                                                         os.path.join(d, "S"), symlinks=True),
                      lambda d: mutate(os.path.join(d, "S"))]
        cases.append(case)

    # --- 1. PNG headers: checked before decoding, in every format that has PNGs --
    for fmt in ("airsim", "bop", "kubric", "replicator", "solo"):
        add_import("png-1e6x1e6", fmt, lambda s: replace_all(s, "*.png", PNG_HUGE),
                   ".png", r"\.png: .*(declares|PNG header)")
        add_import("png-dense", fmt, lambda s: replace_all(s, "*.png", PNG_DENSE),
                   ".png", r"\.png: .*(declares|PNG header)")
    add_import("palette-png-bomb", "kubric",
               lambda s: replace_all(s, "segmentation_*.png", PNG_PALETTE_BOMB),
               "segmentation_", r"\.png: PNG header \(IHDR, byte 16\) declares 40000x40000")

    # --- 2. PFM (AirSim depth) ---------------------------------------------------
    add_import("pfm-18-byte-header", "airsim", lambda s: replace_all(s, "*.pfm", PFM_HUGE),
               ".pfm", r"\.pfm: PFM data is shorter than its header says")
    add_import("pfm-huge-number", "airsim",
               lambda s: replace_all(s, "*.pfm", b"Pf\n99999999999999999999 2\n-1\n" + b"\0" * 8),
               ".pfm", r"\.pfm:2:1: not a PFM file: the width")
    add_import("pfm-sparse-1gib", "airsim", lambda s: sparse_all(s, "*.pfm"),
               ".pfm", r"\.pfm:1:1: not a PFM file")

    # --- 3. EXR through lsds import: the core's header scan first ------------------
    add_import("exr-attribute-bomb", "ue-mrq", lambda s: replace_all(s, "*.exr", EXR_BOMB),
               ".exr", r"\.exr: malformed EXR header: attribute 'comments'")

    # --- 4. .npy headers (Replicator) ------------------------------------------------
    add_import("npy-nested-shape", "replicator", lambda s: replace_all(s, "*.npy", NPY_NESTED),
               ".npy", r"\.npy: bad \.npy header at byte \d+: nesting deeper than 256")
    add_import("npy-nested-field-shape", "replicator",
               lambda s: replace_all(s, "*.npy", NPY_FIELD_NESTED),
               ".npy", r"\.npy: bad \.npy header at byte \d+: nesting deeper than 256")
    add_import("npy-shape-overflow", "replicator",
               lambda s: replace_all(s, "*.npy", NPY_SHAPE_OVERFLOW),
               ".npy", r"\.npy: the \.npy shape overflows")
    add_import("npy-sparse-1gib", "replicator", lambda s: sparse_all(s, "*.npy"),
               ".npy", r"\.npy: not a \.npy file")

    # --- 5. NUL bytes and sparse files in the importers' JSON ---------------------
    for fmt in FORMATS:
        add_import("json-nul", fmt, lambda s: replace_all(s, "*.json", with_nul),
                   ".json", NUL_PLACE)
        add_import("json-sparse-1gib", fmt, lambda s: sparse_all(s, "*.json"),
                   ".json", r"\.json:1:1: a NUL byte")

    # --- 6. NUL bytes in lsds's own JSON inputs -----------------------------------------
    collection = os.path.join(base, "C")
    if not os.path.isdir(collection):
        subprocess.run([lsds, "synth", collection, "--count", "2", "--size", "32x24",
                        "--samples-per-axis", "2"], check=True, stdout=subprocess.DEVNULL)
    reports = os.path.join(base, "reports")
    if not os.path.isdir(reports):
        os.makedirs(reports + ".tmp", exist_ok=True)
        subprocess.run([lsds, "validate", collection, "--format", "json", "-o",
                        os.path.join(reports + ".tmp", "validation.json")],
                       stdout=subprocess.DEVNULL)
        subprocess.run([lsds, "bundles", collection, "-o",
                        os.path.join(reports + ".tmp", "stats.json")],
                       check=True, stdout=subprocess.DEVNULL)
        os.rename(reports + ".tmp", reports)
    examples = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples")
    scene = os.path.join(examples, "uav_survey.lscene")
    capture = os.path.join(examples, "demo_survey.lcap")
    plan = os.path.join(base, "plan.json")
    if not os.path.exists(plan):
        subprocess.run([lsds, "plan", scene, capture, "-o", plan], check=True,
                       stdout=subprocess.DEVNULL)
    scene_json = os.path.join(base, "scene.json")
    if not os.path.exists(scene_json):
        subprocess.run([lsds, "plan", scene, "--emit-json", "-o", scene_json],
                       check=True, stdout=subprocess.DEVNULL)

    def add(case, *setups):
        case.setup = [lambda d: shutil.copytree(collection, os.path.join(d, "C"), symlinks=True),
                      lambda d: shutil.copy(os.path.join(reports, "validation.json"),
                                            os.path.join(d, "validation.json")),
                      lambda d: shutil.copy(os.path.join(reports, "stats.json"),
                                            os.path.join(d, "stats.json")),
                      lambda d: shutil.copy(plan, os.path.join(d, "p.json")),
                      lambda d: shutil.copy(scene_json, os.path.join(d, "s.json")),
                      lambda d: shutil.copy(capture, os.path.join(d, "c.lcap"))] + list(setups)
        cases.append(case)

    readers = {
        "info": "info {d}/C",
        "validate": "validate {d}/C",
        "convert": "convert {d}/C --to coco -o {d}/out",
        "perturb": "perturb-metadata {d}/C --sigma 1 --seed 3 -o {d}/m.json",
    }
    for command, line in readers.items():
        add(Case("json/collection-trailing-nul/" + command, line.split(),
                 names="collection.json", place=NUL_PLACE),
            lambda d: write(os.path.join(d, "C", "collection.json"),
                            with_nul(os.path.join(d, "C", "collection.json"))))
        add(Case("json/collection-sparse-1gib/" + command, line.split(),
                 names="collection.json", place=r"collection\.json:1:1: a NUL byte"),
            lambda d: sparse(os.path.join(d, "C", "collection.json")))
    metadata_readers = {
        "perturb": "perturb-metadata {d}/C --sigma 1 --seed 3 -o {d}/m.json",
        "backproject": "backproject {d}/C -o {d}/cloud.ply --fuse --use-metadata metadata.json",
    }
    for command, line in metadata_readers.items():
        add(Case("json/metadata-trailing-nul/" + command, line.split(),
                 names="metadata.json", place=NUL_PLACE),
            lambda d: write(os.path.join(d, "C", "metadata.json"),
                            with_nul(os.path.join(d, "C", "metadata.json"))))
    files = {
        "plan": ("generate --plan {d}/p.json -o {d}/out -q", "p.json"),
        "lscene-json": ("plan {d}/s.json {d}/c.lcap -o {d}/out.json", "s.json"),
        "validation-report": ("report {d}/C -o {d}/r.html --validation-report {d}/validation.json",
                              "validation.json"),
        "bundle-stats": ("report {d}/C -o {d}/r.html --bundle-stats {d}/stats.json", "stats.json"),
    }
    for label, (line, file) in files.items():
        add(Case("json/%s-trailing-nul" % label, line.split(), names=file, place=NUL_PLACE),
            lambda d, file=file: write(os.path.join(d, file), with_nul(os.path.join(d, file))))
        add(Case("json/%s-sparse-1gib" % label, line.split(), names=file,
                 place=r"%s:1:1: a NUL byte" % file.replace(".", r"\.")),
            lambda d, file=file: sparse(os.path.join(d, file)))
    return cases


def main():
    return corpus_main(__doc__, build_cases, tools=1)



if __name__ == "__main__":
    sys.exit(main())
