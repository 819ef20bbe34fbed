#include "generator/scene/materials.h"

#include <algorithm>
#include <cctype>

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
      {"metal", 1.f, 1.f, 0.35f},
      {"metal_gold", 1.f, 1.f, 0.3f},
      {"plastic", 1.f, 0.f, 0.35f},
      {"rubber", 1.f, 0.f, 0.7f},
      {"painted", 1.f, 0.f, 0.45f},
      {"painted_red", 1.f, 0.f, 0.45f},
      {"painted_green", 1.f, 0.f, 0.45f},
      {"painted_blue", 1.f, 0.f, 0.45f},
      {"painted_yellow", 1.f, 0.f, 0.45f},
      {"asphalt", 0.5f, 0.f, 0.8f},
      {"concrete", 0.5f, 0.f, 0.85f},
  };
  for (Material& m : *table)
    for (const Gloss& g : gloss)
      if (m.name == g.name)
        m.specular = g.specular, m.metallic = g.metallic, m.roughness = g.roughness;
}

}  // namespace

const std::vector<Material>& MaterialTable() {
  static const std::vector<Material> table = [] {
    std::vector<Material> t = {
        // Terrain.
        {"grassy", {0.10f, 0.20f, 0.05f}, {0.22f, 0.26f, 0.09f}, 0.15f, 0.7f},
        {"sandy", {0.55f, 0.45f, 0.30f}, {0.45f, 0.36f, 0.24f}, 0.3f, 0.5f},
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
        // Names used by the LSCENE examples (docs/languages.md).
        {"sand", {0.58f, 0.48f, 0.32f}, {0.48f, 0.39f, 0.26f}, 0.3f, 0.5f},
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
        // Gold's reflectance (F0) in linear RGB, as metals are tinted by it.
        {"metal_gold", {1.00f, 0.71f, 0.29f}, {0.90f, 0.62f, 0.24f}, 4.0f, 0.2f},
    };
    SetSpecular(&t);
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

Eigen::Vector3f Albedo(const Material& material, const Perlin& noise, const Eigen::Vector3f& p) {
  if (material.contrast <= 0) return material.base;
  const double f = material.frequency;
  const double n = noise.Fbm(p.x() * f, p.y() * f, p.z() * f, 3);
  const float mix = std::clamp(static_cast<float>(0.5 + 0.8 * n), 0.f, 1.f) * material.contrast;
  return (1 - mix) * material.base + mix * material.secondary;
}

}  // namespace lsds::gen
