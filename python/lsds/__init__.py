"""lsds: simulated datasets for AI/ML, from Python (docs/python.md).

    import lsds
    c = lsds.open("survey")                  # a collection folder (holds collection.json)
    frame = c[0]                             # or c.frames[0], c.frame(index), c[2:5], for f in c
    depth = frame.layer("depth")             # numpy float32 (H, W), decoded by lsds's readers
    ids = frame.layer("instanceid")          # numpy uint32 (H, W)
    frame.objects, frame.camera.K, frame.camera.cam_from_world, frame.time, frame.metadata
    report = lsds.validate("survey")         # lsds validate as a function: report.findings

The compiled module lsds._lsds does the work; this package re-exports it.
"""

from lsds._lsds import (  # noqa: F401 (re-exported)
    Bundle,
    Camera,
    Collection,
    DataError,
    Error,
    Finding,
    Frame,
    InternalError,
    Location,
    Report,
    UsageError,
    __version__,
    open,
    plugin_search_dirs,
    validate,
)

__all__ = [
    "Bundle",
    "Camera",
    "Collection",
    "DataError",
    "Error",
    "Finding",
    "Frame",
    "InternalError",
    "Location",
    "Report",
    "UsageError",
    "open",
    "plugin_search_dirs",
    "validate",
]
