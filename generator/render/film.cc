#include "generator/render/film.h"

#include "libs/collection/model.h"

namespace lsds::gen {

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
      width,
      height,
      std::vector<uint32_t>(static_cast<size_t>(width) * height, spp));
  for (const LayerChannel& c : StandardLayer("bundle").channels)
    film.bundle.AddChannel(c.name, c.type);
  return film;
}

}  // namespace lsds::gen
