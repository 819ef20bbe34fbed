// The reference renderer's sky and cloud deck as images other renderers read
// (docs/export.md, "Frame description"): the sky's radiance over every direction
// as an equirectangular EXR, and the share of direct sunlight the cloud deck
// lets through as a top-down EXR of the deck, both sampled from
// generator/render/sky.h itself, so that Blender shows and casts the very
// clouds the reference renderer does.
#pragma once

#include <filesystem>
#include <optional>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "generator/render/sky.h"

namespace lsds::gen {

// The sky's equirectangular image size: 2:1, 0.7 degrees a texel.
constexpr int kSkyImageWidth = 512;

// Writes Sky::Radiance over every direction, without the sun's disc (a sun
// lamp stands for it: the disc's directions take the radiance of its rim), as
// a float RGB EXR `width` x `width / 2`: column i and row j (from the top)
// are the direction of longitude 2 pi (i + 0.5) / width - pi (from +x towards
// +y) and latitude pi / 2 - pi (j + 0.5) / (width / 2).
void WriteSkyImage(const Sky& sky, const std::filesystem::path& path, int width = kSkyImageWidth);

// The unit direction of the sky image's texel centre (column, row), as above.
Eigen::Vector3d SkyImageDirection(int width, double column, double row);

// Where and how finely the cloud shadow image samples the deck.
struct CloudShadowArea {
  Eigen::Vector2d min_xy, max_xy;  // the deck's rectangle, world metres
  int width = 0, height = 0;       // texels; texel (i, j) from the top covers
                                   // the deck's x from min_x + i * dx, y from
                                   // max_y - j * dy down
};

// The rectangle of the deck that rays from `ground_min`..`ground_max` (a
// world box) towards the sun cross, with texels of at least 1 m and at most
// 1024 a side. Empty (nullopt) when the sky has no clouds or the sun is
// within 0.01 of the horizon (no cloud shadows, CloudTransmittance).
std::optional<CloudShadowArea> CloudShadowAreaFor(const Sky& sky,
                                                  double cloud_density,
                                                  const Eigen::Vector3d& ground_min,
                                                  const Eigen::Vector3d& ground_max);

// Writes the share of direct sunlight that passes the deck at each texel's
// centre (one float channel, Y) and returns the frame description's
// `clouds` record (docs/export.md).
nlohmann::json WriteCloudShadowImage(const Sky& sky,
                                     const CloudShadowArea& area,
                                     const std::filesystem::path& path);

}  // namespace lsds::gen
