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

#include "libs/collection/model.h"
#include "synth/synthetic_collection.h"

namespace lsds::testing {

// DefaultSpec with one pixel sample and a fifth, oblique and rolled frame
// (the horizon in view, so sky pixels too): the scene the import fixtures are
// synthesized from.
synth::Spec ObliqueImportSpec();

// The instance layer of frame `truth` with the ground (instance 1000) as
// background: the sources label only their objects.
std::vector<uint32_t> TargetIds(const synth::RenderedFrame& truth);

std::string ReadText(const std::filesystem::path& path);

// Intrinsics within `relative` of the truth's (width and height exact), the
// rotation entries and the translation within `pose` (after the importer's
// convention changes).
void ExpectCameraNear(const CameraTruth& got,
                      const CameraTruth& want,
                      double relative,
                      double pose);

// The per-object truth an importer derives (tight box and pixel counts exact,
// visibility and in-frame fraction) and the OBB within `obb` (centre and half
// extents in metres, rotation entries). Ids are the caller's to compare.
void ExpectObjectNear(const ObjectTruth& got, const ObjectTruth& want, double obb);

// `lsds validate --fail-on warning COLLECTION` passes, and `lsds convert COLLECTION --to coco
// --images none -o COCO` succeeds; returns the COCO annotations file (empty on failure).
std::filesystem::path ExpectValidatesAndConvertsToCoco(const std::filesystem::path& collection,
                                                       const std::filesystem::path& coco);

// The fixture's id layer of frame k (what the source's masks hold).
using FixtureIds = std::function<std::vector<uint32_t>(int frame)>;

// Imports `source` with `lsds import FORMAT SOURCE -o DIR/collection FLAGS`,
// then validates and converts it; returns the collection path.
std::filesystem::path ExpectImportValidatesAndConverts(const std::string& format,
                                                       const std::filesystem::path& source,
                                                       const std::filesystem::path& dir,
                                                       int width,
                                                       int height,
                                                       const FixtureIds& fixture_ids,
                                                       const std::string& flags = "");

}  // namespace lsds::testing
