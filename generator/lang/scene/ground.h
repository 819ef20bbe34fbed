// The ground of a scene and where it lies on Earth: the terrain (size, Perlin height, material,
// seed) and the georeference.
#pragma once

#include <cstdint>

#include "generator/lang/random.h"
#include "generator/lang/values.h"
#include "generator/plan/plan.h"

namespace lsds {

// Samples a terrain{...} body into plan->terrain; its class id is the table's "terrain" class.
// The height field's seed is drawn from `seed`'s terrain stream unless the body gives one.
void EvaluateTerrain(const Node& body, uint64_t seed, Rng& rng, Plan* plan);

// Samples the shape keys of a terrain{...} body (`height:{perlin, frequency}`, `perlin`,
// `frequency`, in that order) into `shape`: what the body sets. An LCAP terrain change reads the
// same keys (docs/languages.md, "Terrain shape changes").
void ReadTerrainShape(const Node& body, Rng& rng, PlannedTerrainShape* shape);
// Whether `body` changes the terrain's shape.
bool HasTerrainShape(const Node& body);

// Samples a georeference{latitude, longitude, altitude} body (WGS84, degrees and metres).
GeoOrigin EvaluateGeoreference(const Node& body, Rng& rng);

}  // namespace lsds
