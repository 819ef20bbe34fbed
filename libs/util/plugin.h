// Plug-ins: shared libraries that lsds opens on first use rather than linking, so that the
// libraries behind them (OpenCV's image codecs and GDAL, PCL and VTK, Embree, assimp, Ceres) are
// not loaded by every process at start-up (docs/architecture.md, "Plug-ins").
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

// Throws lsds::Error naming the plug-in unless its table's ABI version (`found`, null when the
// entry point returned no table) is `wanted`.
void CheckPluginAbiVersion(const std::string& file_name, const int* found, int wanted);

// A plug-in's boundary: one extern "C" entry point `entry_symbol` in `file_name` returning a
// const Table* whose first member is `int abi_version`. The table is opened once per process on
// first use (thread-safe static initialisation) and checked against `abi_version`. A failure is
// not cached: the next call retries and throws the same lsds::Error. Each Table type belongs to
// one plug-in.
template <typename Table>
const Table& PluginTable(const char* file_name, const char* entry_symbol, int abi_version) {
  static const Table* const table = [&] {
    using Entry = const Table* (*)();
    const auto entry = reinterpret_cast<Entry>(LoadPluginSymbol(file_name, entry_symbol));
    const Table* loaded = entry();
    CheckPluginAbiVersion(
        file_name, loaded != nullptr ? &loaded->abi_version : nullptr, abi_version);
    return loaded;
  }();
  return *table;
}

}  // namespace lsds
