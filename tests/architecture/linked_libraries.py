#!/usr/bin/env python3
"""The lsds binary links none of the libraries that only plug-ins may load (docs/architecture.md,
"Plug-ins"): OpenCV's imgcodecs (GDAL and ~140 libraries), PCL's io (VTK), Ceres (glog, gflags,
SuiteSparse), assimp (draco, minizip). A product library that links one again would make every command load them at
start-up; this names it.

Usage: linked_libraries.py LSDS_BINARY
"""
import re
import subprocess
import sys

# Only the plug-ins may load these: lsds_image_codecs.so (imgcodecs, GDAL), lsds_cloud_io.so (PCL
# io, VTK), lsds_camera_solver.so (Ceres, static, and the libraries it needs), lsds_mesh_io.so
# (assimp).
PLUGIN_ONLY = re.compile(r"libopencv_imgcodecs|libgdal|libpcl_io|libvtk|"
                         r"libceres|libglog|libgflags|libcholmod|libcxsparse|"
                         r"libassimp|libdraco|libminizip")


def main():
    binary = sys.argv[1]
    listing = subprocess.run(["ldd", binary], capture_output=True, text=True, check=True).stdout
    found = sorted({line.split()[0] for line in listing.splitlines() if PLUGIN_ONLY.search(line)})
    count = len(listing.splitlines())
    if found:
        print(f"{binary} links libraries that only plug-ins may load: {', '.join(found)}")
        return 1
    print(f"{binary}: {count} shared libraries, none of them plug-in-only")
    return 0


if __name__ == "__main__":
    sys.exit(main())
