// Bundle-derived truth layers (docs/bundles.md): majority id, purity, soft
// coverage and the edge mask, written as new layers with semantic "derived"
// next to the existing ones.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "bundles/bundle_stats.h"
#include "libs/collection/model.h"

namespace lsds::bundle {

// "majority", "purity", "coverage", "edge".
const std::vector<std::string>& DerivedLayerNames();

// Parses "majority,purity" (throws lsds::Error naming the unknown name and the
// known ones).
std::vector<std::string> ParseDerivedLayerList(const std::string& list);

// The layer table entry of a derived layer.
LayerInfo DerivedLayer(const std::string& name, bool required);

// The EXR string attribute naming the derived layer a file belongs to. It lets
// a rerun recognise a folder that an interrupted run renamed into place but
// did not register (docs/reliability.md, kill -9).
inline constexpr const char* kDerivedLayerAttribute = "lsdsDerivedLayer";

// Writes the file of derived layer `name` for one frame, from the maps of
// AnalyzeFrame.
void WriteDerivedLayer(const std::string& name,
                       const PixelMaps& maps,
                       int width,
                       int height,
                       const std::filesystem::path& path);

// True when every entry of `folder` is an EXR file of derived layer `name`
// (by its kDerivedLayerAttribute): what an interrupted `--write-layers` run
// leaves, and so what `--force` may replace although collection.json does not
// list it.
bool IsUnregisteredDerivedFolder(const std::filesystem::path& folder, const std::string& name);

}  // namespace lsds::bundle
