// The build tree's copy of generator/cycles/render_frames.py, compiled in from
// one generated file (script_path.cc.in) so that no other compile line holds
// an absolute path.
#pragma once

namespace lsds::gen {

const char* CyclesScriptBuildPath();

}  // namespace lsds::gen
