// A --frames selection checked against a collection's frames: the one check of
// every command that reads part of a collection, and of `import lsds`
// (python/validate_bindings.cc), so that both refuse the same ranges.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "libs/util/frame_selection.h"

namespace lsds {

// The frame indices of the collection at `root`, in increasing order.
std::vector<int64_t> CollectionFrameIndices(const std::filesystem::path& root);

// Parses --frames and checks it against the collection's frames: lsds::Error
// (exit 2) naming the valid range when it reaches outside them. Empty text:
// every frame.
FrameRange SelectCollectionFrames(const std::string& text, const std::filesystem::path& root);

}  // namespace lsds
