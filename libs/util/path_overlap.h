// No output may be, contain or lie inside an input (docs/architecture.md,
// "Nothing is lost").
#pragma once

#include <filesystem>
#include <string>

namespace lsds {

// True when `inner` is `outer` or lies inside it, after resolving symlinks,
// "..", and a trailing "/".
bool PathIsWithin(const std::filesystem::path& inner,
                  const std::filesystem::path& outer);

// Throws lsds::Error located at `output` when it is, lies inside or contains
// `input`. `what` names the input in the message ("input collection").
void RefuseOutputOverlappingInput(const std::filesystem::path& input,
                                  const std::filesystem::path& output,
                                  const std::string& what = "input");

}  // namespace lsds
