#include "libs/collection/residual_layer.h"

#include <algorithm>

#include "libs/collection/float_residual.h"
#include "libs/exr/exr_info.h"
#include "libs/util/error.h"

namespace lsds {

namespace fs = std::filesystem;
using exr::PixelType;

namespace {

bool IsValue(const ResidualLayerKind& kind, const std::string& name) {
  return std::find(kind.values.begin(), kind.values.end(), name) != kind.values.end();
}

std::string Size(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

}  // namespace

bool IsResidualLayer(const exr::ExrInfo& info, const ResidualLayerKind& kind) {
  const auto it = info.attributes.find(kind.layout_attribute);
  return it != info.attributes.end() && it->second == "residual";
}

std::vector<exr::ChannelSpec> ReadableResidualLayerChannels(const exr::ExrInfo& info,
                                                            const ResidualLayerKind& kind) {
  if (!IsResidualLayer(info, kind)) return info.channels;
  std::vector<exr::ChannelSpec> channels;
  for (const exr::ChannelSpec& stored : info.channels) {
    const bool residual = stored.name.size() > 1 && stored.name[0] == 'd' &&
                          IsValue(kind, stored.name.substr(1)) && stored.type == PixelType::kUint;
    channels.push_back(residual ? exr::ChannelSpec{stored.name.substr(1), PixelType::kFloat}
                                : stored);
  }
  std::sort(channels.begin(), channels.end(), [](const auto& a, const auto& b) {
    return a.name < b.name;
  });
  return channels;
}

void WriteResidualLayer(const fs::path& path,
                        const exr::FlatImage& image,
                        const exr::FlatImage& predicted,
                        const ResidualLayerKind& kind,
                        const std::string& depth_layer,
                        const exr::WriteOptions& options) {
  const Location where(path.string());
  if (predicted.width() != image.width() || predicted.height() != image.height()) {
    throw Error("residual " + kind.layer + ": the prediction (depth layer '" + depth_layer +
                    "') is " + Size(predicted.width(), predicted.height()) + " but the layer " +
                    Size(image.width(), image.height()),
                where);
  }
  exr::FlatImage out(image.width(), image.height());
  for (const std::string& name : kind.values) {
    const exr::FlatChannel& truth = image.Get(name);
    if (truth.floats.size() != image.pixel_count() || truth.type != PixelType::kFloat) {
      throw Error("residual " + kind.layer + ": channel " + name + " is not FLOAT", where);
    }
    const std::vector<float>& guess = predicted.Get(name).floats;
    std::vector<uint32_t>& residual = out.AddChannel("d" + name, PixelType::kUint).uints;
    for (size_t p = 0; p < residual.size(); ++p) {
      residual[p] = FoldedDifference(FloatBits(truth.floats[p]), FloatBits(guess[p]));
    }
  }
  exr::WriteOptions write = options;
  write.attributes[kind.layout_attribute] = "residual";
  write.attributes[kind.depth_attribute] = depth_layer;
  exr::WriteFlatExr(path, out, write);
}

exr::FlatImage ReadResidualLayer(const fs::path& path,
                                 const exr::ExrInfo& info,
                                 const std::vector<std::string>& channels,
                                 const ResidualLayerKind& kind,
                                 const ResidualPrediction& predict,
                                 const exr::ReadLimits& limits) {
  const Location where(path.string());
  const std::vector<std::string>& wanted = channels.empty() ? kind.values : channels;
  std::vector<std::string> stored;
  for (const std::string& name : wanted) {
    if (!IsValue(kind, name)) {
      throw Error("residual " + kind.layer + " has no channel '" + name + "'", where);
    }
    const std::string residual = "d" + name;
    const exr::ChannelSpec* spec = info.Find(residual);
    if (spec == nullptr) {
      throw Error(
          "residual " + kind.layer + " has no channel '" + residual + "' (for " + name + ")",
          where);
    }
    if (spec->type != PixelType::kUint) {
      throw Error("residual " + kind.layer + " channel '" + residual + "' is " +
                      exr::PixelTypeName(spec->type) + ", expected uint",
                  where);
    }
    stored.push_back(residual);
  }
  const auto depth_attribute = info.attributes.find(kind.depth_attribute);
  if (depth_attribute == info.attributes.end() || depth_attribute->second.empty()) {
    throw Error("residual " + kind.layer + " has no header attribute '" + kind.depth_attribute +
                    "' naming its depth layer",
                where);
  }
  if (!predict) {
    throw Error("residual " + kind.layer + ": the reader has no depth and camera to predict from",
                where);
  }
  const exr::FlatImage residuals = exr::ReadFlatExr(path, stored, limits);
  exr::FlatImage predicted;
  try {
    predicted = predict(depth_attribute->second);
  } catch (const Error& e) {
    // The depth layer is the one this file's header names: name the file too.
    const std::string inner = e.location().file.empty() ? "" : e.location().ToString() + ": ";
    throw Error("its header attribute '" + kind.depth_attribute + "' names depth layer '" +
                    depth_attribute->second + "', which cannot predict it: " + inner + e.message(),
                where);
  }
  if (predicted.width() != residuals.width() || predicted.height() != residuals.height()) {
    throw Error("residual " + kind.layer + " is " + Size(residuals.width(), residuals.height()) +
                    " but its depth layer '" + depth_attribute->second + "' is " +
                    Size(predicted.width(), predicted.height()),
                where);
  }
  exr::FlatImage out(residuals.width(), residuals.height());
  for (const std::string& name : wanted) {
    const std::vector<uint32_t>& d = residuals.Get("d" + name).uints;
    const std::vector<float>& guess = predicted.Get(name).floats;
    std::vector<float>& value = out.AddChannel(name, PixelType::kFloat).floats;
    for (size_t p = 0; p < value.size(); ++p) {
      value[p] = FloatFromBits(UnfoldedSum(FloatBits(guess[p]), d[p]));
    }
  }
  return out;
}

}  // namespace lsds
