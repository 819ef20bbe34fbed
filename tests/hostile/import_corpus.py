#!/usr/bin/env python3
"""The hostile sources of `lsds import` (docs/reliability.md, docs/import.md
"Confinement" and "Numbers and ids"), run through the CLI with the machinery
of hostile_corpus.py.

Each case copies the import fixture of one format (written once by
write_import_fixture into WORK/base) into its folder, breaks it in one way -
a name in the source's data that is absolute or climbs out with "..", a
symbolic link out of the source, a number written as text that does not fit,
an id outside [0, 2^32), a value of the wrong type, NaN depth - and runs
`lsds import FORMAT SOURCE -o OUT`. Each must exit 2 naming the file and the
place within the time limit, with no crash, no output, and every file of the
case byte-identical. The files links point at lie outside the case folder
(WORK/outside, /etc/hostname): without the confinement rule most cases would
import them and exit 0.

usage: import_corpus.py LSDS WRITE_IMPORT_FIXTURE WORK [--filter SUBSTRING] [--list]
"""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_corpus import Case, corpus_main, tree_state  # noqa: E402

FORMATS = ["ue-mrq", "airsim", "bop", "kubric", "replicator", "solo"]
BIG_ID = 2 ** 32 + 2


def source_of(d, fmt):
    """The folder to give `lsds import` (BOP: the scene folder of the dataset)."""
    return os.path.join(d, "src", "train_pbr", "000000") if fmt == "bop" else os.path.join(d, "src")


def load(path):
    with open(path) as f:
        return json.load(f)


def dump(path, value):
    with open(path, "w") as f:
        json.dump(value, f)


def edit_json(relative, change):
    """A setup: change(document) edits the JSON file at src/relative in place."""
    def setup(d):
        path = os.path.join(d, "src", relative)
        doc = load(path)
        result = change(doc)
        dump(path, doc if result is None else result)
    return setup


def set_at(doc, keys, value):
    for k in keys[:-1]:
        doc = doc[k]
    doc[keys[-1]] = value


def link_out(relative, target):
    """A setup: src/relative becomes a symbolic link to `target` (outside the case)."""
    def setup(d):
        path = os.path.join(d, "src", relative)
        os.remove(path)
        os.symlink(target, path)
    return setup


def build_cases(lsds, writer, work):
    base = os.path.join(work, "base")
    outside = os.path.join(work, "outside")
    os.makedirs(outside, exist_ok=True)

    def fixture(name, fmt, *flags):
        folder = os.path.join(base, name)
        if not os.path.isdir(folder):
            subprocess.run([writer, fmt, folder + ".tmp"] + list(flags), check=True,
                           stdout=subprocess.DEVNULL)
            os.rename(folder + ".tmp", folder)
        return folder

    for fmt in FORMATS:
        fixture(fmt, fmt)
    fixture("solo-nan", "solo", "--nan-depth")
    fixture("kubric-nan", "kubric", "--nan-depth")

    # Valid files outside every case folder: what a hostile source points at.
    def outside_copy(fixture_name, relative):
        target = os.path.join(outside, fixture_name + "-" + os.path.basename(relative))
        if not os.path.exists(target):
            shutil.copyfile(os.path.join(base, fixture_name, relative), target)
        return target

    solo_png = "sequence.0/step0.camera.png"
    rec = load_rec(os.path.join(base, "airsim", "airsim_rec.txt"))
    airsim_scene = "images/" + rec["scene"]

    cases = []

    def add(name, fmt, setups, names, place, fixture_name=None):
        case = Case("import/%s/%s" % (fmt, name),
                    ["import", fmt, "SOURCE", "-o", "{d}/out"], names=names, place=place)
        src_fixture = os.path.join(base, fixture_name or fmt)

        def copy(d, src_fixture=src_fixture):
            shutil.copytree(src_fixture, os.path.join(d, "src"), symlinks=True)
        case.setup = [copy] + list(setups)
        case.fmt = fmt
        cases.append(case)

    # --- reads outside the source: names in data, links ------------------------
    add("filename-absolute", "solo",
        [edit_json("sequence.0/step0.frame_data.json",
                   lambda j: set_at(j, ["captures", 0, "filename"], outside_copy("solo", solo_png)))],
        "step0.frame_data.json", r"#/captures/0/filename.*is absolute")
    add("filename-dotdot", "solo",
        [lambda d: edit_json("sequence.0/step0.frame_data.json", lambda j: set_at(
            j, ["captures", 0, "filename"],
            os.path.relpath(outside_copy("solo", solo_png), os.path.join(d, "src", "sequence.0"))))(d)],
        "step0.frame_data.json", r"#/captures/0/filename.*leaves the source")
    add("link-outside", "solo", [link_out(solo_png, outside_copy("solo", solo_png))],
        "step0.frame_data.json", r"#/captures/0/filename.*outside the source")
    if os.path.exists("/etc/hostname"):
        add("link-etc-hostname", "solo",
            [link_out("annotation_definitions.json", "/etc/hostname")],
            "annotation_definitions.json", r"/etc/hostname.*outside the source")
    add("imagefile-dotdot", "airsim",
        [lambda d: replace_in(os.path.join(d, "src", "airsim_rec.txt"), rec["scene"],
                              os.path.relpath(outside_copy("airsim", airsim_scene),
                                              os.path.join(d, "src", "images")))],
        "airsim_rec.txt", r"airsim_rec\.txt:2:\d+.*leaves the source")
    add("imagefile-absolute", "airsim",
        [lambda d: replace_in(os.path.join(d, "src", "airsim_rec.txt"), rec["scene"],
                              outside_copy("airsim", airsim_scene))],
        "airsim_rec.txt", r"airsim_rec\.txt:2:\d+.*is absolute")
    add("link-outside", "airsim", [link_out(airsim_scene, outside_copy("airsim", airsim_scene))],
        "airsim_rec.txt", r"airsim_rec\.txt:2:\d+.*outside the source")
    add("link-outside", "bop",
        [link_out("train_pbr/000000/depth/000000.png",
                  outside_copy("bop", "train_pbr/000000/depth/000000.png"))],
        "000000.png", r"outside the source")
    add("link-outside", "kubric", [link_out("rgba_00000.png", outside_copy("kubric", "rgba_00000.png"))],
        "rgba_00000.png", r"outside the source")
    add("link-outside", "replicator",
        [link_out("camera_params_0000.json", outside_copy("replicator", "camera_params_0000.json"))],
        "camera_params_0000.json", r"outside the source")
    add("link-outside", "ue-mrq", [link_out("Shot.0000.exr", outside_copy("ue-mrq", "Shot.0000.exr"))],
        "Shot.0000.exr", r"outside the source")
    add("sidecar-link-outside", "ue-mrq",
        [link_out("lsds_objects.json", outside_copy("ue-mrq", "lsds_objects.json"))],
        "lsds_objects.json", r"outside the source")

    # --- numbers written as text that do not fit (were std::stoll) --------------
    add("image-key-overflow", "bop",
        [edit_json("train_pbr/000000/scene_camera.json",
                   lambda j: set_at(j, ["99999999999999999999"], j["0"]))],
        "scene_camera.json", r"#/99999999999999999999.*not an image id")
    add("image-key-text", "bop",
        [edit_json("train_pbr/000000/scene_camera.json", lambda j: set_at(j, ["x1"], j["0"]))],
        "scene_camera.json", r"#/x1.*not an image id")
    add("frame-number-overflow", "replicator",
        [lambda d: shutil.copyfile(os.path.join(d, "src", "rgb_0000.png"),
                                   os.path.join(d, "src", "rgb_99999999999999999999.png"))],
        "rgb_99999999999999999999.png", r"beyond")
    add("colour-key-overflow", "replicator",
        [edit_json("instance_segmentation_mapping_0000.json",
                   lambda j: set_at(j, ["(99999999999, 0, 0, 255)"], "BACKGROUND"))],
        "instance_segmentation_mapping_0000.json", r"#/\(99999999999, 0, 0, 255\).*colour key")
    add("sequence-overflow", "solo",
        [lambda d: os.rename(os.path.join(d, "src", "sequence.1"),
                             os.path.join(d, "src", "sequence.99999999999999999999"))],
        "sequence.99999999999999999999", r"beyond")

    # --- ids outside [0, 2^32): refused, never wrapped ----------------------------
    add("class-id-2^32+2", "airsim",
        [edit_json("lsds_objects.json", lambda j: set_at(j, ["classes", 0, "id"], BIG_ID))],
        "lsds_objects.json", r"#/classes/0/id.*4294967298")
    add("instance-id-minus-1", "airsim",
        [edit_json("lsds_objects.json", lambda j: set_at(j, ["objects", 0, "instance_id"], -1))],
        "lsds_objects.json", r"#/objects/0/instance_id.*-1")
    add("class-id-2^32+2", "ue-mrq",
        [edit_json("lsds_objects.json", lambda j: set_at(j, ["classes", 0, "id"], BIG_ID))],
        "lsds_objects.json", r"#/classes/0/id.*4294967298")
    add("instance-id-minus-1", "ue-mrq",
        [edit_json("lsds_objects.json", lambda j: set_at(j, ["actors", 0, "instance_id"], -1))],
        "lsds_objects.json", r"#/actors/0/instance_id.*-1")
    add("label-id-2^32+2", "solo",
        [edit_json("sequence.0/step0.frame_data.json", lambda j: set_at(
            j, ["captures", 0, "annotations", 0, "instances", 0, "labelId"], BIG_ID))],
        "step0.frame_data.json", r"#/captures/0/annotations/0/instances/0/labelId.*4294967298")
    add("instance-id-minus-1", "solo",
        [edit_json("sequence.0/step0.frame_data.json", lambda j: set_at(
            j, ["captures", 0, "annotations", 1, "values", 0, "instanceId"], -1))],
        "step0.frame_data.json", r"#/captures/0/annotations/1/values/0/instanceId.*-1")
    add("label-id-definitions-2^32+2", "solo",
        [edit_json("annotation_definitions.json", lambda j: set_at(
            j, ["annotationDefinitions", 0, "spec", 0, "label_id"], BIG_ID))],
        "annotation_definitions.json", r"#/annotationDefinitions/0/spec/0/label_id")
    add("model-key-4294967297", "bop",
        [edit_json("models/models_info.json", lambda j: set_at(j, ["4294967297"], j["1"]))],
        "models_info.json", r"#/4294967297.*not an obj_id")
    add("obj-id-4294967297", "bop",
        [edit_json("train_pbr/000000/scene_gt.json", lambda j: set_at(j, ["0", 0, "obj_id"], 2 ** 32 + 1))],
        "scene_gt.json", r"#/0/0/obj_id.*4294967297")

    # --- values of the wrong type ---------------------------------------------------
    add("prim-path-not-string", "replicator",
        [edit_json("instance_segmentation_mapping_0000.json",
                   lambda j: set_at(j, [sorted(j)[0]], 5))],
        "instance_segmentation_mapping_0000.json", r"#/\(.*expected a string")
    add("box-prim-path-not-string", "replicator",
        [edit_json("bounding_box_3d_prim_paths_0000.json", lambda j: set_at(j, [0], {"a": 1}))],
        "bounding_box_3d_prim_paths_0000.json", r"#/0.*expected a string")
    add("actor-name-not-string", "ue-mrq",
        [edit_json("lsds_objects.json", lambda j: set_at(j, ["actors", 0, "name"], [1]))],
        "lsds_objects.json", r"#/actors/0/name.*expected a string")
    add("filename-not-string", "solo",
        [edit_json("sequence.0/step0.frame_data.json", lambda j: set_at(j, ["captures", 0, "filename"], 7))],
        "step0.frame_data.json", r"#/captures/0/filename.*expected a string")

    # --- NaN depth: a broken file, not sky --------------------------------------------
    add("nan-depth", "solo", [], "step0.camera.Depth.exr", r"frame 0 pixel \(3, 2\).*NaN",
        fixture_name="solo-nan")
    add("nan-depth", "kubric", [], "depth_00000.tiff", r"frame 0 pixel \(3, 2\).*NaN",
        fixture_name="kubric-nan")

    for case in cases:
        case.args = [a if a != "SOURCE" else "{d}/src" + ("/train_pbr/000000" if case.fmt == "bop" else "")
                     for a in case.args]
    return cases


def load_rec(path):
    """The first row's Scene image name of an airsim_rec.txt."""
    with open(path) as f:
        header, row = f.readline().rstrip("\n").split("\t"), f.readline().rstrip("\n").split("\t")
    names = row[header.index("ImageFile")].split(";")
    return {"scene": next(n for n in names if "_0_" in n)}


def replace_in(path, old, new):
    with open(path) as f:
        text = f.read()
    assert old in text
    with open(path, "w") as f:
        f.write(text.replace(old, new, 1))


def main():
    outside = []

    def prepare(lsds, work):
        outside.append(os.path.join(work, "outside"))
        return snapshot(outside[0])

    # The files the links point at are inputs too.
    def finish(before):
        return [] if snapshot(outside[0]) == before else ["the files outside the sources changed"]

    return corpus_main(__doc__, build_cases, tools=1, prepare=prepare, finish=finish)


def snapshot(folder):
    return tree_state(folder)


if __name__ == "__main__":
    sys.exit(main())
