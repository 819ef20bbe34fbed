"""PyTorch datasets over lsds collections (docs/python.md, "PyTorch").

    from torch.utils.data import DataLoader
    from lsds.torch import FrameDataset, collate

    data = FrameDataset("survey", layers=["rgb", "depth", "instanceid"])
    loader = DataLoader(data, batch_size=8, shuffle=True, num_workers=4, collate_fn=collate)
    for batch in loader:
        batch["layers"]["depth"]   # float32 (B, 1, H, W)
        batch["boxes"]             # list of B float32 (N, 4) tensors

Needs PyTorch (Debian's python3-torch); `import lsds` alone does not.
"""
import torch

import lsds

__all__ = ["FrameDataset", "collate"]


def _tensor(array):
    """A layer array as a tensor: uint32 ids become int64 (torch has no uint32; lossless). The
    module gives (C, H, W) itself when asked (Frame.layer(..., channels_first=True)): no copy here."""
    if array.dtype == "uint32":
        array = array.astype("int64")
    return torch.from_numpy(array)


class FrameDataset(torch.utils.data.Dataset):
    """The frames of a collection as samples (dicts of tensors and truth).

    path: the collection folder. layers: the flat layers to decode (default: rgb). frames: a
    slice or range of frame positions (default: every frame). channels_first: layers as (C, H, W)
    tensors (default) or as lsds gives them, (H, W) / (H, W, C). transform: a function applied to
    each sample dict. The collection is opened in the process that makes the dataset; DataLoader
    workers that fork share it, and workers that spawn open it again (the dataset pickles as its
    arguments).
    """

    def __init__(self, path, layers=("rgb",), frames=None, channels_first=True, transform=None):
        self.path = str(path)
        self.layers = list(layers)
        self.channels_first = channels_first
        self.transform = transform
        self._collection = lsds.open(self.path)
        names = {layer["name"] for layer in self._collection.layers if not layer["deep"]}
        unknown = [name for name in self.layers if name not in names]
        if unknown:
            raise lsds.UsageError(f"{self.path}: no flat layer {', '.join(map(repr, unknown))} "
                                  f"(flat layers: {', '.join(sorted(names))})")
        everything = range(len(self._collection))
        self.positions = list(everything if frames is None else everything[frames])

    def __len__(self):
        return len(self.positions)

    def __getitem__(self, i):
        frame = self._collection[self.positions[i]]
        boxes, labels, instances = [], [], []
        for o in frame.objects:
            if o.get("bbox") is not None:
                boxes.append(o["bbox"])
                labels.append(o["class_id"])
                instances.append(o["instance_id"])
        sample = {
            "index": frame.index,
            "time": frame.time,
            "layers": {name: _tensor(frame.layer(name, channels_first=self.channels_first))
                       for name in self.layers},
            "K": torch.from_numpy(frame.camera.K),
            "cam_from_world": torch.from_numpy(frame.camera.cam_from_world),
            "boxes": torch.tensor(boxes, dtype=torch.float32).reshape(-1, 4),
            "labels": torch.tensor(labels, dtype=torch.int64),
            "instance_ids": torch.tensor(instances, dtype=torch.int64),
            "objects": frame.objects,
        }
        return self.transform(sample) if self.transform else sample

    def __getstate__(self):
        state = dict(self.__dict__)
        del state["_collection"]  # an open collection does not pickle; spawned workers reopen it
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self._collection = lsds.open(self.path)


def collate(samples):
    """A batch of FrameDataset samples: layers, K and cam_from_world stacked (frames of one size),
    index and time as tensors, boxes, labels, instance_ids and objects as lists (one per frame)."""
    batch = {
        "index": torch.tensor([s["index"] for s in samples], dtype=torch.int64),
        "time": torch.tensor([s["time"] for s in samples], dtype=torch.float64),
        "layers": {name: torch.stack([s["layers"][name] for s in samples])
                   for name in samples[0]["layers"]},
        "K": torch.stack([s["K"] for s in samples]),
        "cam_from_world": torch.stack([s["cam_from_world"] for s in samples]),
    }
    for key in ("boxes", "labels", "instance_ids", "objects"):
        batch[key] = [s[key] for s in samples]
    return batch
