// Plug-ins: shared libraries that lsds opens on first use rather than linking, so that the
// libraries behind them (OpenCV's image codecs and the ~140 libraries GDAL pulls in) are not
// loaded by every process at start-up.
#pragma once

#include <string>
#include <vector>

namespace lsds {

// The folders searched for a plug-in, in order:
//   1. $LSDS_PLUGIN_DIR, when set and not empty;
//   2. <folder of the running executable>/../lib/lsds (where `cmake --install` puts them);
//   3. when lsds's code runs from a shared object rather than the executable (the Python module
//      PREFIX/lib/python3/dist-packages/lsds/_lsds*.so, which python3 loads): the installed
//      plug-in folder relative to that object's folder, PREFIX/lib/lsds (found with dladdr);
//   4. the build tree's plug-in folder (compiled in from one generated file,
//      libs/util/plugin_build_dir.cc.in, so that test binaries anywhere in the build, and the
//      Python module in the build tree, find it).
std::vector<std::string> PluginSearchDirs();

// The address of `symbol` in the plug-in `file_name` (e.g. "lsds_image_codecs.so"), opened from
// the first folder of PluginSearchDirs() that holds it. The library stays loaded for the life of
// the process. Throws lsds::Error naming every path tried and dlerror()'s message when no folder
// holds a plug-in that opens and exports `symbol`.
void* LoadPluginSymbol(const std::string& file_name, const std::string& symbol);

}  // namespace lsds
