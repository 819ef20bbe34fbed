#include "generator/scene_export/texture_export.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include <opencv2/core.hpp>

#include "libs/exr/flat_image.h"
#include "libs/imaging/srgb_image.h"
#include "libs/util/srgb.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;

// Within this of an 8-bit sRGB code's linear value, a texel is that code read by
// generator/scene/texture.cc (which rounds through OpenCV's float conversion); neighbouring codes
// lie at least 1 / (255 * 12.92) = 3e-4 apart.
constexpr float kSrgb8Tolerance = 1e-6f;

// The 8-bit sRGB byte a texel was read from, if it was.
std::optional<uint8_t> ExactSrgb8(float v) {
  if (!(v >= 0.f && v <= 1.f)) return std::nullopt;
  const auto byte =
      static_cast<uint8_t>(std::lround(std::clamp(SrgbFromLinear(v), 0.0, 1.0) * 255));
  if (std::abs(LinearFromSrgb8(byte) - v) > kSrgb8Tolerance) return std::nullopt;
  return byte;
}

// The map as 8-bit sRGB BGR (OpenCV's order) when every texel came from 8-bit sRGB (a PNG or
// JPEG source: the file holds the source's bytes again), else empty.
cv::Mat ExactSrgb8Image(const ImageTexture& map) {
  cv::Mat bgr(map.height, map.width, CV_8UC3);
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const Eigen::Vector3f& c = map.texels[static_cast<size_t>(y) * map.width + x];
      cv::Vec3b& out = bgr.at<cv::Vec3b>(y, x);
      for (int a = 0; a < 3; ++a) {
        const std::optional<uint8_t> byte = ExactSrgb8(c[a]);
        if (!byte) return {};
        out[2 - a] = *byte;
      }
    }
  }
  return bgr;
}

}  // namespace

std::string TextureExporter::FileOf(const ImageTexture& map) {
  const auto known = files_.find(&map);
  if (known != files_.end()) return known->second;
  const std::string stem = "textures/texture_" + std::to_string(files_.size());
  fs::create_directories(folder_ / "textures");
  std::string file;
  if (const cv::Mat bgr = ExactSrgb8Image(map); !bgr.empty()) {
    file = stem + ".png";  // 8-bit sRGB, lossless
    imaging::WriteImage(folder_ / file, bgr, imaging::DisplayOptions{});
  } else {
    file = stem + ".exr";  // 16-bit or float sources: linear float RGB
    exr::FlatImage image(map.width, map.height);
    exr::FlatChannel* rgb[3] = {&image.AddChannel("R", exr::PixelType::kFloat),
                                &image.AddChannel("G", exr::PixelType::kFloat),
                                &image.AddChannel("B", exr::PixelType::kFloat)};
    for (size_t p = 0; p < map.texels.size(); ++p)
      for (int a = 0; a < 3; ++a) rgb[a]->floats[p] = map.texels[p][a];
    exr::WriteFlatExr(folder_ / file, image);
  }
  files_.emplace(&map, file);
  return file;
}

std::vector<AlbedoPart> TextureExporter::Split(const TriangleMesh& mesh) {
  if (mesh.albedo_maps.empty() || mesh.triangle_map.size() != mesh.triangles.size() ||
      mesh.uvs.size() != mesh.positions.size())
    return {};
  std::vector<int> maps(mesh.triangle_map);
  std::sort(maps.begin(), maps.end());
  maps.erase(std::unique(maps.begin(), maps.end()), maps.end());
  const bool normals = mesh.corner_normals.size() == 3 * mesh.triangles.size();
  std::vector<AlbedoPart> parts;
  for (const int map : maps) {
    AlbedoPart albedo;
    albedo.record = nlohmann::json::object();
    if (map >= 0) {
      const ImageTexture& image = *mesh.albedo_maps[map];
      if (image.width == 1 && image.height == 1) {
        albedo.constant = true;
        albedo.colour = image.texels.front();
        albedo.record["albedo"] = {albedo.colour.x(), albedo.colour.y(), albedo.colour.z()};
      } else {
        albedo.record["albedo_map"] = FileOf(image);
      }
    }
    // Maps of the same albedo (a car's four tyres) are one part.
    auto part = std::find_if(
        parts.begin(), parts.end(), [&](const AlbedoPart& p) { return p.record == albedo.record; });
    if (part == parts.end()) {
      albedo.mesh.positions = mesh.positions;
      albedo.mesh.uvs = mesh.uvs;
      parts.push_back(std::move(albedo));
      part = parts.end() - 1;
    }
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.triangle_map[t] != map) continue;
      part->mesh.triangles.push_back(mesh.triangles[t]);
      if (normals)
        part->mesh.corner_normals.insert(part->mesh.corner_normals.end(),
                                         mesh.corner_normals.begin() + 3 * t,
                                         mesh.corner_normals.begin() + 3 * t + 3);
    }
  }
  return parts;
}

}  // namespace lsds::gen
