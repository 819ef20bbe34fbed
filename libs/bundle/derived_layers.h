// Bundle-derived truth layers (docs/bundles.md): majority id, purity, soft
// coverage and the edge mask, written as new layers with semantic "derived"
// next to the existing ones.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "libs/bundle/bundle_stats.h"
#include "libs/collection/model.h"

namespace lsds::bundle {

// "majority", "purity", "coverage", "edge".
const std::vector<std::string>& DerivedLayerNames();

// Parses "majority,purity" (throws lsds::Error naming the unknown name and the
// known ones).
std::vector<std::string> ParseDerivedLayerList(const std::string& list);

// The layer table entry of a derived layer.
LayerInfo DerivedLayer(const std::string& name, bool required);

// Writes the file of derived layer `name` for one frame, from the maps of
// AnalyzeFrame.
void WriteDerivedLayer(const std::string& name,
                       const PixelMaps& maps,
                       int width,
                       int height,
                       const std::filesystem::path& path);

}  // namespace lsds::bundle
