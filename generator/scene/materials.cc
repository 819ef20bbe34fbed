#include "generator/scene/materials.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::gen {

namespace {

// Glossy and metallic materials: (specular, metallic, roughness) on top of
// their albedo table row.
void SetSpecular(std::vector<Material>* table) {
  struct Gloss {
    const char* name;
    float specular, metallic, roughness;
  };
  static const Gloss gloss[] = {
      {"metal", 1.f, 1.f, 0.35f},          {"metal_gold", 1.f, 1.f, 0.3f},
      {"plastic", 1.f, 0.f, 0.35f},        {"rubber", 1.f, 0.f, 0.7f},
      {"painted", 1.f, 0.f, 0.45f},        {"painted_red", 1.f, 0.f, 0.45f},
      {"painted_green", 1.f, 0.f, 0.45f},  {"painted_blue", 1.f, 0.f, 0.45f},
      {"painted_yellow", 1.f, 0.f, 0.45f}, {"car_white", 1.f, 0.f, 0.3f},
      {"car_black", 1.f, 0.f, 0.3f},       {"car_grey", 1.f, 0.f, 0.3f},
      {"car_silver", 1.f, 0.f, 0.3f},      {"car_blue", 1.f, 0.f, 0.3f},
      {"car_red", 1.f, 0.f, 0.3f},         {"car_beige", 1.f, 0.f, 0.3f},
      {"car_green", 1.f, 0.f, 0.3f},       {"asphalt", 0.5f, 0.f, 0.8f},
      {"concrete", 0.5f, 0.f, 0.85f},
  };
  for (Material& m : *table)
    for (const Gloss& g : gloss)
      if (m.name == g.name)
        m.specular = g.specular, m.metallic = g.metallic, m.roughness = g.roughness;
}

// The spatial variation of the built-in families: (pattern, patches).
void SetPatterns(std::vector<Material>* table) {
  struct Variation {
    const char* name;
    Pattern pattern;
    float patches;
  };
  static const Variation variation[] = {
      {"grassy", Pattern::kMottled, 0.35f},      {"grass", Pattern::kMottled, 0.35f},
      {"sandy", Pattern::kSpeckle, 0.15f},       {"sand", Pattern::kSpeckle, 0.15f},
      {"rocky_sand", Pattern::kSpeckle, 0.2f},   {"rocky", Pattern::kStrata, 0.25f},
      {"granite", Pattern::kSpeckle, 0.15f},     {"stone", Pattern::kStrata, 0.2f},
      {"sandstone", Pattern::kStrata, 0.2f},     {"snowy", Pattern::kMottled, 0.05f},
      {"soil", Pattern::kMottled, 0.3f},         {"mud", Pattern::kMottled, 0.3f},
      {"asphalt", Pattern::kSpeckle, 0.25f},     {"concrete", Pattern::kSpeckle, 0.15f},
      {"metal", Pattern::kBrushed, 0.1f},        {"metal_gold", Pattern::kBrushed, 0.05f},
      {"rust", Pattern::kMottled, 0.3f},         {"painted", Pattern::kMottled, 0.1f},
      {"painted_red", Pattern::kMottled, 0.1f},  {"painted_green", Pattern::kMottled, 0.1f},
      {"painted_blue", Pattern::kMottled, 0.1f}, {"painted_yellow", Pattern::kMottled, 0.1f},
      {"wood", Pattern::kBrushed, 0.15f},        {"foliage", Pattern::kMottled, 0.3f},
  };
  for (Material& m : *table)
    for (const Variation& v : variation)
      if (m.name == v.name) m.pattern = v.pattern, m.patches = v.patches;
}

// The terrain families' fine detail (ground_detail.h, docs/generator.md
// "Ground detail"): wavelengths from clumps and patches down to blades,
// grains and aggregate.
void SetDetail(std::vector<Material>* table) {
  struct Fine {
    const char* name;
    float contrast, coarsest_m, finest_m, persistence;
    bool ridged;
    float bump;
  };
  static const Fine fine[] = {
      {"grassy", 0.5f, 0.32f, 0.01f, 0.95f, true, 0.6f},
      {"grass", 0.5f, 0.32f, 0.01f, 0.95f, true, 0.6f},
      {"sandy", 0.15f, 0.16f, 0.002f, 0.85f, false, 0.15f},
      {"sand", 0.15f, 0.16f, 0.002f, 0.85f, false, 0.15f},
      {"rocky_sand", 0.25f, 0.32f, 0.004f, 0.85f, false, 0.25f},
      {"rocky", 0.3f, 0.64f, 0.005f, 0.8f, false, 0.35f},
      {"stone", 0.3f, 0.64f, 0.005f, 0.8f, false, 0.35f},
      {"sandstone", 0.25f, 0.64f, 0.005f, 0.8f, false, 0.3f},
      {"granite", 0.25f, 0.32f, 0.003f, 0.85f, false, 0.25f},
      {"soil", 0.35f, 0.32f, 0.005f, 0.85f, false, 0.3f},
      {"mud", 0.25f, 0.32f, 0.005f, 0.8f, false, 0.15f},
      {"asphalt", 0.4f, 0.08f, 0.002f, 0.95f, false, 0.2f},
      {"concrete", 0.15f, 0.16f, 0.002f, 0.85f, false, 0.1f},
      {"snowy", 0.06f, 0.64f, 0.01f, 0.75f, false, 0.1f},
  };
  for (Material& m : *table) {
    for (const Fine& f : fine) {
      if (m.name != f.name) continue;
      m.detail.contrast = f.contrast;
      m.detail.coarsest_m = f.coarsest_m;
      m.detail.finest_m = f.finest_m;
      m.detail.persistence = f.persistence;
      m.detail.ridged = f.ridged;
      m.detail.bump = f.bump;
      // Grass: the bright blade tips are dry, yellower.
      if (f.ridged) m.detail.tint = Eigen::Vector3f(1.3f, 1.1f, 0.5f);
    }
  }
}

}  // namespace

const std::vector<Material>& MaterialTable() {
  static const std::vector<Material> table = [] {
    std::vector<Material> t = {
        // Terrain.
        {"grassy", {0.10f, 0.20f, 0.05f}, {0.22f, 0.26f, 0.09f}, 0.15f, 0.7f},
        // Dry sand: albedo 0.3-0.4 (luminance 0.37 and 0.30).
        {"sandy", {0.44f, 0.36f, 0.25f}, {0.36f, 0.29f, 0.20f}, 0.3f, 0.5f},
        {"rocky", {0.28f, 0.26f, 0.24f}, {0.45f, 0.43f, 0.40f}, 0.4f, 0.8f},
        {"snowy", {0.80f, 0.82f, 0.85f}, {0.65f, 0.68f, 0.74f}, 0.2f, 0.4f},
        {"soil", {0.20f, 0.13f, 0.08f}, {0.30f, 0.22f, 0.14f}, 0.5f, 0.6f},
        {"mud", {0.12f, 0.09f, 0.06f}, {0.18f, 0.15f, 0.10f}, 0.4f, 0.5f},
        {"asphalt", {0.06f, 0.06f, 0.06f}, {0.10f, 0.10f, 0.10f}, 2.0f, 0.5f},
        // Objects.
        {"concrete", {0.40f, 0.40f, 0.38f}, {0.32f, 0.32f, 0.30f}, 3.0f, 0.4f},
        {"metal", {0.56f, 0.57f, 0.58f}, {0.45f, 0.46f, 0.47f}, 4.0f, 0.3f},
        {"rust", {0.30f, 0.12f, 0.05f}, {0.45f, 0.22f, 0.10f}, 3.0f, 0.6f},
        {"rubber", {0.03f, 0.03f, 0.03f}, {0.05f, 0.05f, 0.05f}, 8.0f, 0.3f},
        {"plastic", {0.60f, 0.60f, 0.60f}, {0.55f, 0.55f, 0.55f}, 4.0f, 0.1f},
        {"wood", {0.35f, 0.22f, 0.10f}, {0.25f, 0.15f, 0.07f}, 6.0f, 0.6f},
        {"fabric", {0.15f, 0.18f, 0.30f}, {0.10f, 0.12f, 0.22f}, 10.0f, 0.3f},
        {"foliage", {0.05f, 0.16f, 0.04f}, {0.12f, 0.25f, 0.06f}, 5.0f, 0.7f},
        {"stone", {0.32f, 0.30f, 0.27f}, {0.20f, 0.19f, 0.18f}, 2.0f, 0.6f},
        {"painted_red", {0.55f, 0.05f, 0.04f}, {0.45f, 0.05f, 0.04f}, 4.0f, 0.2f},
        {"painted_green", {0.10f, 0.25f, 0.08f}, {0.08f, 0.20f, 0.06f}, 4.0f, 0.2f},
        {"painted_blue", {0.05f, 0.12f, 0.45f}, {0.04f, 0.10f, 0.38f}, 4.0f, 0.2f},
        {"painted_yellow", {0.70f, 0.55f, 0.05f}, {0.60f, 0.45f, 0.04f}, 4.0f, 0.2f},
        {"white", {0.80f, 0.80f, 0.80f}, {0.75f, 0.75f, 0.75f}, 1.0f, 0.0f},
        {"orange", {0.80f, 0.30f, 0.03f}, {0.70f, 0.25f, 0.03f}, 1.0f, 0.1f},
        // Names used by the LSCENE examples (docs/languages.md) and the paper's text ("grass").
        {"grass", {0.10f, 0.20f, 0.05f}, {0.22f, 0.26f, 0.09f}, 0.15f, 0.7f},
        {"sand", {0.46f, 0.38f, 0.26f}, {0.37f, 0.30f, 0.21f}, 0.3f, 0.5f},
        {"rocky_sand", {0.45f, 0.39f, 0.30f}, {0.30f, 0.28f, 0.25f}, 0.6f, 0.7f},
        {"granite", {0.35f, 0.33f, 0.32f}, {0.55f, 0.52f, 0.50f}, 5.0f, 0.6f},
        {"sandstone", {0.55f, 0.38f, 0.22f}, {0.45f, 0.30f, 0.18f}, 3.0f, 0.5f},
        {"olive", {0.20f, 0.22f, 0.08f}, {0.16f, 0.18f, 0.06f}, 4.0f, 0.2f},
        {"red", {0.55f, 0.05f, 0.04f}, {0.45f, 0.05f, 0.04f}, 4.0f, 0.2f},
        {"green", {0.08f, 0.30f, 0.06f}, {0.06f, 0.24f, 0.05f}, 4.0f, 0.2f},
        {"blue", {0.05f, 0.12f, 0.45f}, {0.04f, 0.10f, 0.38f}, 4.0f, 0.2f},
        {"yellow", {0.70f, 0.55f, 0.05f}, {0.60f, 0.45f, 0.04f}, 4.0f, 0.2f},
        {"black", {0.03f, 0.03f, 0.03f}, {0.04f, 0.04f, 0.04f}, 4.0f, 0.2f},
        {"painted", {0.30f, 0.32f, 0.20f}, {0.25f, 0.26f, 0.16f}, 4.0f, 0.3f},
        // Car paints (builtin_meshes.h CarPaint): lacquered, glossy (SetSpecular), hardly
        // patterned; linear albedos of white, black, grey, silver, ... bodywork.
        {"car_white", {0.78f, 0.78f, 0.76f}, {0.74f, 0.74f, 0.72f}, 4.0f, 0.1f},
        {"car_black", {0.02f, 0.02f, 0.022f}, {0.03f, 0.03f, 0.032f}, 4.0f, 0.1f},
        {"car_grey", {0.15f, 0.155f, 0.16f}, {0.13f, 0.135f, 0.14f}, 4.0f, 0.1f},
        {"car_silver", {0.45f, 0.46f, 0.47f}, {0.40f, 0.41f, 0.42f}, 4.0f, 0.1f},
        {"car_blue", {0.03f, 0.07f, 0.25f}, {0.03f, 0.06f, 0.21f}, 4.0f, 0.1f},
        {"car_red", {0.42f, 0.03f, 0.03f}, {0.36f, 0.03f, 0.03f}, 4.0f, 0.1f},
        {"car_beige", {0.45f, 0.38f, 0.27f}, {0.40f, 0.34f, 0.24f}, 4.0f, 0.1f},
        {"car_green", {0.05f, 0.14f, 0.07f}, {0.04f, 0.12f, 0.06f}, 4.0f, 0.1f},
        // Gold's reflectance (F0) in linear RGB, as metals are tinted by it.
        {"metal_gold", {1.00f, 0.71f, 0.29f}, {0.90f, 0.62f, 0.24f}, 4.0f, 0.2f},
    };
    SetSpecular(&t);
    SetPatterns(&t);
    SetDetail(&t);
    return t;
  }();
  return table;
}

const std::vector<std::string>& MaterialNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const Material& m : MaterialTable()) n.push_back(m.name);
    return n;
  }();
  return names;
}

namespace {

// Names match case-insensitively and without '_' or '-': "MetalGold" is
// "metal_gold".
std::string Canonical(const std::string& name) {
  std::string out;
  for (char c : name) {
    if (c != '_' && c != '-' && c != ' ')
      out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

}  // namespace

const Material& FindMaterial(const std::string& name, const std::string& where) {
  const std::string canonical = Canonical(name);
  for (const Material& m : MaterialTable()) {
    if (Canonical(m.name) == canonical) return m;
  }
  throw Error(where + ": unknown material '" + name + "'" + DidYouMean(name, MaterialNames()) +
              "; known: " + Join(MaterialNames(), ", "));
}

Eigen::Vector3f Albedo(const Material& material,
                       const Perlin& noise,
                       const Eigen::Vector3f& p,
                       float footprint_m,
                       Eigen::Vector2f* tilt,
                       bool height_field) {
  if (tilt != nullptr) tilt->setZero();
  if (material.contrast <= 0 && material.patches <= 0) return material.base;
  const double f = material.frequency;
  double n = 0;
  switch (material.pattern) {
    case Pattern::kMottled:
      n = noise.Fbm(p.x() * f, p.y() * f, p.z() * f, 3);
      break;
    case Pattern::kSpeckle: {
      // Mottling plus grains: a fine noise, thresholded, at 8x the frequency.
      const double grain = noise.Noise(p.x() * f * 8 + 31.7, p.y() * f * 8, p.z() * f * 8);
      n = 0.6 * noise.Fbm(p.x() * f, p.y() * f, p.z() * f, 2) + (grain > 0.25 ? 0.8 : -0.1);
      break;
    }
    case Pattern::kStrata: {
      // Bedding planes: bands along z, bent by noise.
      const double warp = noise.Fbm(p.x() * f * 0.5, p.y() * f * 0.5, p.z() * f * 0.5, 2);
      n = 0.7 * std::sin((p.z() * f * 3 + 2.5 * warp) * M_PI) +
          0.4 * noise.Noise(p.x() * f * 4, p.y() * f * 4, p.z() * f * 4);
      break;
    }
    case Pattern::kBrushed:
      // Streaks: noise stretched 40 times along x.
      n = noise.Fbm(p.x() * f * 0.1, p.y() * f * 4, p.z() * f * 4, 2);
      break;
  }
  const float mix = std::clamp(static_cast<float>(0.5 + 0.8 * n), 0.f, 1.f) * material.contrast;
  Eigen::Vector3f albedo = (1 - mix) * material.base + mix * material.secondary;
  if (material.patches > 0) {
    const double g = f / 8;
    const double patch = noise.Fbm(p.x() * g + 113.1, p.y() * g + 71.3, p.z() * g, 2);
    albedo *= std::clamp(1.f + material.patches * static_cast<float>(patch) * 1.5f, 0.f, 2.f);
  }
  if (material.detail.contrast > 0)
    albedo = albedo.cwiseProduct(
        DetailFactor(material.detail, noise, p, footprint_m, tilt, height_field));
  return albedo.cwiseMin(1.f);
}

double AlbedoReuseDistance(const Material& material, float footprint_m) {
  const double f = material.frequency;
  // The highest frequency (cycles/m) of each term of Albedo above.
  double finest = 0;
  if (material.contrast > 0) {
    switch (material.pattern) {
      case Pattern::kMottled:
        finest = 4 * f;  // three octaves from f
        break;
      case Pattern::kSpeckle:
        return 0;  // the grains are a step function
      case Pattern::kStrata:
        finest = 16 * f;  // detail at 4f, bands whose warp makes them up to 4x steeper
        break;
      case Pattern::kBrushed:
        finest = 8 * f;  // two octaves from 4f across the streaks
        break;
    }
  }
  if (material.patches > 0) finest = std::max(finest, f / 4);  // two octaves from f / 8
  if (material.detail.contrast > 0) {
    // Ridges (1 - 2 |noise|) are twice as steep as the noise.
    const double ridges = material.detail.ridged ? 2 : 1;
    finest = std::max(finest, ridges / DetailFinestWavelength(material.detail, footprint_m));
  }
  if (finest <= 0) return std::numeric_limits<double>::infinity();
  return 1 / (32 * finest);
}

}  // namespace lsds::gen
