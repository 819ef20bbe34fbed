#include "generator/render/film.h"

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

Film Film::Make(int width, int height, int spp, bool with_bundle) {
  Film film;
  for (const std::string& semantic : StandardLayerSemantics()) {
    const LayerInfo layer = StandardLayer(semantic);
    if (layer.deep) continue;
    exr::FlatImage image(width, height);
    for (const LayerChannel& c : layer.channels) {
      image.AddChannel(c.name,
                       c.type);  // HALF channels hold floats until written
    }
    film.flat.emplace(semantic, std::move(image));
  }
  film.centre_sample.resize(static_cast<size_t>(width) * height);
  if (!with_bundle) return film;
  film.bundle = exr::DeepImage(
      width, height, std::vector<uint32_t>(static_cast<size_t>(width) * height, spp));
  for (const LayerChannel& c : StandardLayer("bundle").channels)
    film.bundle.AddChannel(c.name, c.type);
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
