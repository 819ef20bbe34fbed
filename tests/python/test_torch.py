"""lsds.torch: FrameDataset samples equal the frames' layers and truth; collate; DataLoader workers
(fork and spawn) give the batches a single process gives."""
import pickle

import pytest

import lsds

torch = pytest.importorskip("torch")
from lsds.torch import FrameDataset, collate  # noqa: E402 (needs torch)


def test_samples_equal_the_frames(demo_residual):
    data = FrameDataset(demo_residual, layers=["depth", "normal", "instanceid"])
    c = lsds.open(demo_residual)
    assert len(data) == len(c) == 2
    sample = data[1]
    frame = c[1]
    assert sample["index"] == frame.index
    assert torch.equal(sample["layers"]["depth"], torch.from_numpy(frame.layer("depth"))[None])
    assert sample["layers"]["normal"].shape == (3, 16, 24)
    assert torch.equal(sample["layers"]["normal"].permute(1, 2, 0), torch.from_numpy(frame.layer("normal")))
    ids = sample["layers"]["instanceid"]
    assert ids.dtype == torch.int64 and (ids[0].numpy() == frame.layer("instanceid")).all()
    visible = [o for o in frame.objects if o["bbox"] is not None]
    assert sample["boxes"].shape == (len(visible), 4)
    assert sample["labels"].tolist() == [o["class_id"] for o in visible]
    assert torch.equal(sample["K"], torch.from_numpy(frame.camera.K))
    assert FrameDataset(demo_residual, frames=slice(1, None), channels_first=False)[0]["layers"]["rgb"].shape == (16, 24, 3)


def test_unknown_layer(demo_residual):
    with pytest.raises(lsds.UsageError, match="dpth"):
        FrameDataset(demo_residual, layers=["dpth"])


def batches(loader):
    return [(b["index"].tolist(), b["layers"]["depth"].sum().item(), [x.tolist() for x in b["boxes"]])
            for b in loader]


def test_dataloader_workers(demo_residual):
    data = FrameDataset(demo_residual, layers=["depth", "instanceid"])
    single = batches(torch.utils.data.DataLoader(data, batch_size=2, collate_fn=collate))
    assert single[0][0] == [0, 1]
    forked = torch.utils.data.DataLoader(data, batch_size=1, num_workers=2, collate_fn=collate,
                                         multiprocessing_context="fork")
    assert [b[0][0] for b in batches(forked)] == [0, 1]
    batch = collate([data[0], data[1]])
    assert batch["layers"]["instanceid"].shape == (2, 1, 16, 24)
    assert batch["K"].shape == (2, 3, 3) and len(batch["objects"]) == 2
    # Pickled (spawned workers): the dataset reopens the collection.
    again = pickle.loads(pickle.dumps(data))
    assert torch.equal(again[1]["layers"]["depth"], data[1]["layers"]["depth"])
