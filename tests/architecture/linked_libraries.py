#!/usr/bin/env python3
"""The lsds binary and the Python module link none of the libraries that only plug-ins may load
(docs/architecture.md, "Plug-ins"): OpenCV's imgcodecs (GDAL and ~140 libraries), PCL's io (VTK),
Ceres (glog, gflags, SuiteSparse), assimp (draco, minizip) and Embree. A product library that
links one again would make every command (and `import lsds`) load them at start-up; this names it.

Usage: linked_libraries.py BINARY_OR_MODULE...
"""
import re
import subprocess
import sys

# Only the plug-ins may load these: lsds_image_codecs.so (imgcodecs, GDAL), lsds_cloud_io.so (PCL
# io, VTK), lsds_camera_solver.so (Ceres, static, and the libraries it needs), lsds_mesh_io.so
# (assimp), lsds_embree.so (Embree).
PLUGIN_ONLY = re.compile(r"libopencv_imgcodecs|libgdal|libpcl_io|libvtk|"
                         r"libceres|libglog|libgflags|libcholmod|libcxsparse|"
                         r"libassimp|libdraco|libminizip|libembree")


def main():
    failed = 0
    for binary in sys.argv[1:]:
        listing = subprocess.run(["ldd", binary], capture_output=True, text=True,
                                 check=True).stdout
        found = sorted({line.split()[0] for line in listing.splitlines()
                        if PLUGIN_ONLY.search(line)})
        count = len(listing.splitlines())
        if found:
            print(f"{binary} links libraries that only plug-ins may load: {', '.join(found)}")
            failed = 1
        else:
            print(f"{binary}: {count} shared libraries, none of them plug-in-only")
    return failed


if __name__ == "__main__":
    sys.exit(main())
