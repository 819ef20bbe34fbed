// The build tree's plug-in folder, from one generated file (libs/util/plugin_build_dir.cc.in).
#pragma once

namespace lsds {

// Compiled in from a single generated file rather than a compile definition, so that no other
// compile line holds an absolute path and ccache shares objects between checkouts.
const char* PluginBuildDir();

}  // namespace lsds
