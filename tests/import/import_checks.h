// The end-to-end checks every imported fixture goes through, as a user meets
// them: `lsds import`, `lsds validate --fail-on warning`, `lsds convert` to
// COCO (masks decoded with pycocotools' RLE rule equal the fixture's id layer)
// and to YOLO (labels denormalise to the truth's boxes).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace lsds::testing {

// The fixture's id layer of frame k (what the source's masks hold).
using FixtureIds = std::function<std::vector<uint32_t>(int frame)>;

// Imports `source` with `lsds import FORMAT SOURCE -o DIR/collection FLAGS`,
// then validates and converts it; returns the collection path.
std::filesystem::path ExpectImportValidatesAndConverts(
    const std::string& format,
    const std::filesystem::path& source,
    const std::filesystem::path& dir,
    int width,
    int height,
    const FixtureIds& fixture_ids,
    const std::string& flags = "");

}  // namespace lsds::testing
