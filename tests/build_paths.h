// The folders of this checkout and of its build, for tests and benchmarks that run the lsds binary
// or read the examples.
#pragma once

#include <string>

namespace lsds::testing {

// They come from one generated file (tests/build_paths.cc.in) rather than from compile
// definitions, so that no other compile line holds an absolute path and ccache can share objects
// between checkouts (CI's fresh clone reuses what any earlier build on the machine compiled).
const std::string& SourceDir();  // the repository root
const std::string& BinaryDir();  // the CMake build folder
std::string ExamplesDir();       // SourceDir()/examples

}  // namespace lsds::testing
