#include "bundles/derived_layers.h"

#include <algorithm>

#include "libs/exr/deep_image.h"
#include "libs/exr/exr_info.h"
#include "libs/exr/flat_image.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::bundle {

using exr::PixelType;

const std::vector<std::string>& DerivedLayerNames() {
  static const std::vector<std::string> names = {"majority", "purity", "coverage", "edge"};
  return names;
}

std::vector<std::string> ParseDerivedLayerList(const std::string& list) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= list.size()) {
    const size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    start = comma + 1;
    if (name.empty()) continue;
    const auto& known = DerivedLayerNames();
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      throw Error("--write-layers: unknown layer '" + name + "'" + DidYouMean(name, known) +
                  "; known: " + Join(known, ", "));
    }
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
  }
  if (out.empty()) throw Error("--write-layers: no layer named");
  return out;
}

LayerInfo DerivedLayer(const std::string& name, bool required) {
  LayerInfo layer;
  layer.name = name;
  layer.semantic = "derived";
  layer.required = required;
  layer.compression = exr::Compression::kZip;
  if (name == "majority") {
    layer.channels = {{"instanceid", PixelType::kUint}, {"classid", PixelType::kUint}};
    layer.unit = "id";
    layer.description =
        "lsds bundles: the instance id holding most samples of the pixel "
        "bundle (ties: the one seen "
        "first, sample 0 nearest the centre) and its class id; 0 background";
  } else if (name == "purity") {
    layer.channels = {{"Y", PixelType::kFloat}};
    layer.unit = "ratio";
    layer.description =
        "lsds bundles: share of the pixel's samples holding the majority "
        "instance id, in (0, 1]; 0 "
        "for pixels without samples";
  } else if (name == "coverage") {
    layer.deep = true;
    layer.compression = exr::Compression::kZips;
    layer.channels = {{"instanceid", PixelType::kUint},
                      {"classid", PixelType::kUint},
                      {"coverage", PixelType::kFloat}};
    layer.unit = "ratio";
    layer.description =
        "lsds bundles: soft coverage, one deep sample per instance id in the "
        "pixel bundle with the "
        "share of samples holding it, by share descending; shares sum to 1";
  } else if (name == "edge") {
    layer.channels = {{"Y", PixelType::kUint}};
    layer.unit = "mask";
    layer.description =
        "lsds bundles: 1 where the pixel holds more than one instance id or "
        "depths farther apart than "
        "the flying threshold (labels or depth uncertain), else 0";
  } else {
    throw Error("unknown derived layer '" + name + "'");
  }
  return layer;
}

void WriteDerivedLayer(const std::string& name,
                       const PixelMaps& maps,
                       int width,
                       int height,
                       const std::filesystem::path& path) {
  exr::WriteOptions options;
  const LayerInfo layer = DerivedLayer(name, true);
  options.compression = layer.compression;
  options.attributes[kDerivedLayerAttribute] = name;
  if (name == "coverage") {
    exr::DeepImage image(width, height, maps.coverage_counts);
    image.AddChannel("instanceid", PixelType::kUint).uints = maps.coverage_instance;
    image.AddChannel("classid", PixelType::kUint).uints = maps.coverage_class;
    image.AddChannel("coverage", PixelType::kFloat).floats = maps.coverage;
    exr::WriteDeepExr(path, image, options);
    return;
  }
  exr::FlatImage image(width, height);
  if (name == "majority") {
    image.AddChannel("instanceid", PixelType::kUint).uints = maps.majority_instance;
    image.AddChannel("classid", PixelType::kUint).uints = maps.majority_class;
  } else if (name == "purity") {
    image.AddChannel("Y", PixelType::kFloat).floats = maps.purity;
  } else if (name == "edge") {
    image.AddChannel("Y", PixelType::kUint).uints.assign(maps.edge.begin(), maps.edge.end());
  } else {
    throw Error("unknown derived layer '" + name + "'");
  }
  exr::WriteFlatExr(path, image, options);
}

bool IsUnregisteredDerivedFolder(const std::filesystem::path& folder, const std::string& name) {
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) return false;
  for (std::filesystem::directory_iterator it(folder, ec), end; it != end; it.increment(ec)) {
    if (ec || !it->is_regular_file(ec) || it->path().extension() != ".exr") return false;
    try {
      const exr::ExrInfo info = exr::ReadExrInfo(it->path());
      const auto found = info.attributes.find(kDerivedLayerAttribute);
      if (found == info.attributes.end() || found->second != name) return false;
    } catch (const Error&) {
      return false;  // not an EXR lsds wrote: never replaced
    }
  }
  return !ec;
}

}  // namespace lsds::bundle
