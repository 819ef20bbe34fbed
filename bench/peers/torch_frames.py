"""bench_python's Python side: frames/s through lsds.torch's FrameDataset and a DataLoader.

    python3 torch_frames.py COLLECTION --layers rgb,depth,... [--workers 0,2] [--batch 4]
                            [--repeats 3]

For each worker count: one warm-up epoch (the workers start and the page cache fills), then the
best of --repeats epochs over every frame, batches collated by lsds.torch.collate. The workers are
persistent, so an epoch is decoding, collating and moving tensors, not process start-up. Prints one
JSON object: {"workers": {"0": frames_per_s, "2": ...}, "frames": N}. Needs PYTHONPATH to hold the
lsds package (build/<preset>/python) and PyTorch (Debian's python3-torch).
"""
import argparse
import json
import time

import torch
from torch.utils.data import DataLoader

from lsds.torch import FrameDataset, collate


def epoch_seconds(loader):
    start = time.perf_counter()
    frames = 0
    for batch in loader:
        frames += len(batch["index"])
    return time.perf_counter() - start, frames


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("collection")
    parser.add_argument("--layers", required=True)
    parser.add_argument("--workers", default="0,2")
    parser.add_argument("--batch", type=int, default=4)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    torch.set_num_threads(1)  # the floor decodes on one thread; collate's stack likewise
    data = FrameDataset(args.collection, layers=args.layers.split(","))
    result = {"frames": len(data), "workers": {}}
    for workers in (int(w) for w in args.workers.split(",")):
        loader = DataLoader(data, batch_size=args.batch, num_workers=workers, collate_fn=collate,
                            persistent_workers=workers > 0)
        epoch_seconds(loader)  # warm-up
        best = min(epoch_seconds(loader)[0] for _ in range(args.repeats))
        result["workers"][str(workers)] = len(data) / best
        del loader
    print(json.dumps(result))


if __name__ == "__main__":
    main()
