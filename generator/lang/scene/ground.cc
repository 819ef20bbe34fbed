#include "generator/lang/scene/ground.h"

#include "generator/lang/vocabulary.h"
#include "generator/scene/vegetation.h"

namespace lsds {
namespace {

// A sampled number of the key `key` of the table `kind`, within its range.
double Sampled(const Node& n, const char* kind, const char* key, Rng& rng) {
  return SampleInRange(n, KindVocabulary(kind).Key(key), rng);
}

// `perlin:A` or `perlin:{amplitude, frequency}`.
void ReadPerlin(const Node& p, Rng& rng, PlannedTerrainShape* t) {
  if (p->is_object()) {
    CheckKeys(p, KindVocabulary("perlin"), "Perlin");
    if (const Node a = p.Find("amplitude"))
      t->perlin_amplitude = Sampled(a, "perlin", "amplitude", rng);
    if (const Node f = p.Find("frequency"))
      t->perlin_frequency = Sampled(f, "perlin", "frequency", rng);
  } else {
    t->perlin_amplitude = Sampled(p, "perlin", "amplitude", rng);
  }
}

// `vegetation:{density, kind, height}`: the scatter's seed from the scene seed's terrain stream.
void ReadVegetation(const Node& v, uint64_t seed, Rng& rng, PlannedVegetation* out) {
  CheckKeys(v, KindVocabulary("vegetation"), "vegetation");
  const Node density = v.Find("density");
  if (!density) v.Fail("vegetation needs a density (plants per m^2)");
  out->density = Sampled(density, "vegetation", "density", rng);
  if (const Node k = v.Find("kind")) {
    out->kind = SampleString(k, rng);
    if (out->kind != "grass" && out->kind != "plants")
      k.Fail("vegetation kind must be grass or plants, not '" + out->kind + "'");
  }
  if (const Node h = v.Find("height")) out->height_m = Sampled(h, "vegetation", "height", rng);
  constexpr uint64_t kVegetationKey = 0x76656765;  // "vege"
  out->seed = MixKey(MixKey(seed, static_cast<uint64_t>(StreamTag::kTerrain)), kVegetationKey) >>
              11;  // 53 bits: exact in JSON
}

}  // namespace

void ReadTerrainShape(const Node& b, Rng& rng, PlannedTerrainShape* shape) {
  if (const Node n = b.Find("height")) {
    CheckKeys(n, KindVocabulary("terrain_height"), "terrain height");
    if (const Node p = n.Find("perlin")) ReadPerlin(p, rng, shape);
    if (const Node f = n.Find("frequency"))
      shape->perlin_frequency = Sampled(f, "terrain_height", "frequency", rng);
  }
  if (const Node p = b.Find("perlin")) ReadPerlin(p, rng, shape);
  if (const Node f = b.Find("frequency"))
    shape->perlin_frequency = Sampled(f, "terrain", "frequency", rng);
}

bool HasTerrainShape(const Node& b) {
  return b.Find("height") || b.Find("perlin") || b.Find("frequency");
}

void EvaluateTerrain(const Node& b, uint64_t seed, Rng& rng, Plan* plan) {
  PlannedTerrain& t = plan->terrain;
  t.present = true;
  t.perlin_seed =
      MixKey(seed, static_cast<uint64_t>(StreamTag::kTerrain)) >> 11;  // 53 bits: exact in JSON
  if (const Node n = b.Find("size")) {
    t.size = SampleVec2(n, rng);
    CheckRange(n, KindVocabulary("terrain").Key("size"), t.size.minCoeff());
  }
  PlannedTerrainShape shape;
  ReadTerrainShape(b, rng, &shape);
  if (shape.perlin_amplitude) t.perlin_amplitude = *shape.perlin_amplitude;
  if (shape.perlin_frequency) t.perlin_frequency = *shape.perlin_frequency;
  if (const Node m = b.Find("material")) t.material = SampleString(m, rng);
  if (const Node s = b.Find("seed"))
    t.perlin_seed = static_cast<uint64_t>(ReadInRange(s, KindVocabulary("terrain").Key("seed")));
  if (const Node v = b.Find("vegetation")) {
    ReadVegetation(v, seed, rng, &t.vegetation);
    if (gen::PlantCount(t) > gen::kMaxPlants)
      v.Fail("vegetation: " + std::to_string(gen::PlantCount(t)) +
             " plants over this terrain is over the limit of " + std::to_string(gen::kMaxPlants) +
             "; lower the density or the terrain's size");
  }
  for (const ClassInfo& c : plan->classes)
    if (c.name == "terrain") t.class_id = c.id;
}

GeoOrigin EvaluateGeoreference(const Node& b, Rng& rng) {
  GeoOrigin geo;
  if (const Node w = b.Find("wgs84")) {
    if (b.Find("latitude") || b.Find("longitude") || b.Find("altitude"))
      w.Fail("give wgs84:[latitude, longitude, altitude] or the separate keys, not both");
    if (!w->is_array() || (w->size() != 2 && w->size() != 3))
      w.Fail("wgs84 is [latitude, longitude] or [latitude, longitude, altitude]");
    const KindSpec& vocabulary = KindVocabulary("georeference");
    geo.latitude_deg = SampleInRange(w.Item(0), vocabulary.Key("latitude"), rng);
    geo.longitude_deg = SampleInRange(w.Item(1), vocabulary.Key("longitude"), rng);
    if (w->size() == 3) geo.altitude_m = SampleScalar(w.Item(2), rng);
    return geo;
  }
  const Node latitude = b.Find("latitude"), longitude = b.Find("longitude");
  if (!latitude) b.Fail("a georeference needs a latitude and a longitude (WGS84, deg)");
  geo.latitude_deg = Sampled(latitude, "georeference", "latitude", rng);
  if (!longitude) b.Fail("a georeference needs a latitude and a longitude (WGS84, deg)");
  geo.longitude_deg = Sampled(longitude, "georeference", "longitude", rng);
  if (const Node n = b.Find("altitude")) geo.altitude_m = SampleScalar(n, rng);
  return geo;
}

}  // namespace lsds
