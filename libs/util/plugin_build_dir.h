// The build tree's plug-in folder and the installed Python package's way to the installed one,
// from one generated file (libs/util/plugin_build_dir.cc.in).
#pragma once

namespace lsds {

// Compiled in from a single generated file rather than a compile definition, so that no other
// compile line holds an absolute path and ccache shares objects between checkouts.
const char* PluginBuildDir();

// The installed plug-in folder relative to the installed Python package's folder (the folder of
// its module _lsds*.so): "../../../lsds" for PREFIX/lib/python3/dist-packages/lsds and
// PREFIX/lib/lsds, from the same generated file.
const char* PluginDirFromPythonPackage();

}  // namespace lsds
