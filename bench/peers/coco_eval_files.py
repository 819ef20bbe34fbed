"""bench_evaluate's peer: pycocotools' COCOeval (iouType bbox) on the files `bench_evaluate --write
DIR` keeps.

    python3 coco_eval_files.py --pycocotools /tmp/cocoapi/PythonAPI GT.json DT.json

pycocotools is not a dependency of lsds: build it from source in a scratch folder as the README.md
of tests/evaluate says (its code never enters the repository). Loading (COCO(), loadRes)
and evaluating (evaluate, accumulate, summarize) are timed apart, each in wall and CPU seconds
(user + system of this process). Prints one JSON object: {"load_wall_s", "load_cpu_s",
"eval_wall_s", "eval_cpu_s", "stats": the 12 numbers}.
"""
import argparse
import contextlib
import io
import json
import os
import sys
import time


def cpu_seconds():
    t = os.times()
    return t.user + t.system


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pycocotools", required=True, help="the PythonAPI folder of cocoapi")
    parser.add_argument("ground_truth")
    parser.add_argument("results")
    args = parser.parse_args()

    # The import the goldens' script makes (stubs for what the evaluation does not use).
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                    "tests", "evaluate"))
    import make_goldens
    COCO, COCOeval = make_goldens.import_pycocotools(args.pycocotools)

    wall, cpu = time.perf_counter(), cpu_seconds()
    with contextlib.redirect_stdout(io.StringIO()):
        truth = COCO(args.ground_truth)
        results = truth.loadRes(args.results)
    load_wall, load_cpu = time.perf_counter() - wall, cpu_seconds() - cpu

    wall, cpu = time.perf_counter(), cpu_seconds()
    with contextlib.redirect_stdout(io.StringIO()):
        e = COCOeval(truth, results, "bbox")
        e.evaluate()
        e.accumulate()
        e.summarize()
    eval_wall, eval_cpu = time.perf_counter() - wall, cpu_seconds() - cpu
    print(json.dumps({"load_wall_s": round(load_wall, 2), "load_cpu_s": round(load_cpu, 2),
                      "eval_wall_s": round(eval_wall, 2), "eval_cpu_s": round(eval_cpu, 2),
                      "stats": [float(s) for s in e.stats]}))


if __name__ == "__main__":
    main()
