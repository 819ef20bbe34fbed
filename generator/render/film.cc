#include "generator/render/film.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>

#include "libs/collection/model.h"

namespace lsds::gen {

uint64_t Film::BytesPerPixel(int spp, bool with_bundle) {
  uint64_t bytes = sizeof(Eigen::Vector2f);  // centre_sample
  for (const std::string& semantic : StandardLayerSemantics()) {
    const LayerInfo layer = StandardLayer(semantic);
    if (!layer.deep) bytes += 4 * layer.channels.size();
  }
  if (with_bundle) {
    // Sample counts, offsets and spp samples of every bundle channel.
    bytes += sizeof(uint32_t) + sizeof(uint64_t) +
             static_cast<uint64_t>(std::max(1, spp)) * 4 * StandardLayer("bundle").channels.size();
  }
  return bytes;
}

namespace {

std::vector<exr::ChannelSpec> Specs(const LayerInfo& layer) {
  std::vector<exr::ChannelSpec> specs;
  for (const LayerChannel& c : layer.channels) specs.push_back({c.name, c.type});
  return specs;
}

}  // namespace

// A film is a few hundred MB of fresh pages: every layer and channel is
// zero-filled in parallel, as a single core faulting them in would take a
// tenth of a frame's render time (docs/generator.md "Performance").
Film Film::Make(int width, int height, int spp, bool with_bundle) {
  Film film;
  std::vector<exr::FlatImage*> flat;
  std::vector<LayerInfo> layers;
  for (const std::string& semantic : StandardLayerSemantics()) {
    LayerInfo layer = StandardLayer(semantic);
    if (layer.deep) continue;
    flat.push_back(&film.flat.emplace(semantic, exr::FlatImage(width, height)).first->second);
    layers.push_back(std::move(layer));
  }
  tbb::parallel_invoke(
      [&] {
        // HALF channels hold floats until written.
        tbb::parallel_for(
            size_t{0}, flat.size(), [&](size_t l) { flat[l]->AddChannels(Specs(layers[l])); });
      },
      [&] { film.centre_sample.resize(static_cast<size_t>(width) * height); },
      [&] {
        if (!with_bundle) return;
        film.bundle = exr::DeepImage(
            width, height, std::vector<uint32_t>(static_cast<size_t>(width) * height, spp));
        film.bundle.AddChannels(Specs(StandardLayer("bundle")));
      });
  return film;
}

void Film::Reshape(int width, int height, int spp, bool with_bundle, Film* film) {
  const auto rgb = film->flat.find("rgb");
  const bool same_flat =
      rgb != film->flat.end() && rgb->second.width() == width && rgb->second.height() == height;
  const uint64_t samples = static_cast<uint64_t>(width) * height * std::max(1, spp);
  const bool same_bundle = with_bundle
                               ? film->bundle.width() == width && film->bundle.height() == height &&
                                     film->bundle.total_samples() == samples
                               : film->bundle.pixel_count() == 0;
  if (!same_flat || !same_bundle) *film = Make(width, height, spp, with_bundle);
  film->rays = 0;
}

}  // namespace lsds::gen
