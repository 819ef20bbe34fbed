// Flat layers stored as exact residuals of a prediction from the frame's depth
// layer and camera (docs/format.md "Worldposition layouts", "Motion
// layouts"): each FLOAT value channel V is stored as a UINT channel dV =
// FoldedDifference(bits(V), bits(predicted V)) (libs/collection/float_residual.h),
// and the header names the layout and the depth layer the prediction reads.
// The codec and the one reader shared by the worldposition and motion layers;
// only their predictions differ.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "libs/exr/exr_types.h"
#include "libs/exr/flat_image.h"

namespace lsds {

struct ResidualLayerKind {
  std::string layer;                // "worldposition": for messages
  std::vector<std::string> values;  // {"X", "Y", "Z"}; the residual of V is "d" + V
  std::string layout_attribute;     // the header attribute that says "residual"
  std::string depth_attribute;      // the header attribute naming the depth layer
};

bool IsResidualLayer(const exr::ExrInfo& info, const ResidualLayerKind& kind);

// The channels a reader gets from a residual file with header `info` (V FLOAT
// for each stored dV UINT; other channels as stored), sorted by name; other
// files: their channels.
std::vector<exr::ChannelSpec> ReadableResidualLayerChannels(const exr::ExrInfo& info,
                                                            const ResidualLayerKind& kind);

// Writes the value channels of `image` as residuals of `predicted` (the same
// channels, FLOAT, the same size), with the layout and depth attributes.
void WriteResidualLayer(const std::filesystem::path& path,
                        const exr::FlatImage& image,
                        const exr::FlatImage& predicted,
                        const ResidualLayerKind& kind,
                        const std::string& depth_layer,
                        const exr::WriteOptions& options);

// The prediction of a file's values from the depth layer its header names.
using ResidualPrediction = std::function<exr::FlatImage(const std::string& depth_layer)>;

// Reads the named value channels (all when empty) of a residual file with
// header `info`: FLOAT, bit for bit what the float layout stores. Throws
// lsds::Error naming the file for missing or non-UINT residual channels, a
// missing depth attribute or a prediction of another size.
exr::FlatImage ReadResidualLayer(const std::filesystem::path& path,
                                 const exr::ExrInfo& info,
                                 const std::vector<std::string>& channels,
                                 const ResidualLayerKind& kind,
                                 const ResidualPrediction& predict,
                                 const exr::ReadLimits& limits);

}  // namespace lsds
