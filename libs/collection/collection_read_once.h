// Reading a collection with collection.json read once where the file allows:
// the header from the members before "frames" (lsds writes the frames last),
// every frame's syntax checked as the frames stream instead of at open.
// CollectionReader reads the file twice (a syntax check of the whole file at
// open, then the frames); a command that reads the frames once anyway
// (`lsds info`) reads it through this instead.
#pragma once

#include <filesystem>
#include <functional>

#include <nlohmann/json.hpp>

#include "libs/collection/collection_reader.h"
#include "libs/collection/model.h"

namespace lsds {

// Streams the frames as CollectionReader::ForEachFrame does.
using ForEachFrameFn = std::function<void(const std::function<void(const Frame&)>&)>;
// What ReadCollectionOnce runs: the header, and the frames to stream once.
using ReadCollection = std::function<void(const CollectionHeader&, const ForEachFrameFn&)>;

// Opens the collection at `root` and runs `read`, which streams the frames.
// A bad file is the same lsds::Error, at the same line:column or JSON pointer,
// as CollectionReader reports, thrown while the frames stream (a file that is
// wrong in more than one place may report another of its errors first). Where
// members follow the frames, the header before them was not all of it: `read`
// runs again, on the header and frames of a CollectionReader (so `read` must
// start from nothing each time). Returns the header of the last run.
CollectionHeader ReadCollectionOnce(const std::filesystem::path& root,
                                    const ReadCollection& read,
                                    ReaderOptions options = {});

// The header of the collection.json at `path` from the members before
// "frames" alone (left an empty array), nothing after the array's '[' read;
// false when the file does not fit the fast split (ReadJsonTextBeforeArray).
bool ReadCollectionHeaderBeforeFrames(const std::filesystem::path& path, nlohmann::json* header);

// StreamCollectionFrames that also gives the members but the frames in
// `*header` (when not null), as ReadCollectionHeader does. Returns the number
// of frames.
size_t StreamCollectionFramesAndHeader(
    const std::filesystem::path& path,
    const std::function<void(Frame&&, size_t index)>& on_frame,
    const std::function<void(nlohmann::json&&, size_t index)>& on_json,
    CollectionReader::FramePath frame_path,
    nlohmann::json* header);

}  // namespace lsds
