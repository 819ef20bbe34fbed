// Image textures of loaded assets (glTF/OBJ base-colour maps): linear RGB
// texels read with OpenCV, sampled bilinearly with wrap-around (glTF's default
// REPEAT sampler). Shading reads them; the truth layers never do.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace lsds::gen {

struct ImageTexture {
  int width = 0, height = 0;
  std::vector<Eigen::Vector3f> texels;  // linear RGB, row-major, row 0 the image's top row

  // Bilinear, wrapped. `uv` in assimp's convention: (0, 0) the image's
  // bottom-left corner, v up (assimp flips glTF's top-left origin on import).
  Eigen::Vector3f Sample(const Eigen::Vector2f& uv) const;
};

// Reads an image file (PNG, JPEG, ... whatever OpenCV decodes); 8-bit images
// are sRGB-encoded and turned linear, 16-bit ones likewise, float ones are
// taken as linear. Throws lsds::Error naming `where` and the file.
std::shared_ptr<const ImageTexture> LoadImageTexture(const std::string& path,
                                                     const std::string& where);
// The same from encoded bytes (a glb's embedded PNG or JPEG).
std::shared_ptr<const ImageTexture> DecodeImageTexture(const unsigned char* bytes,
                                                       size_t size,
                                                       const std::string& where);
// From raw 8-bit sRGB RGB texels, row 0 at the top.
std::shared_ptr<const ImageTexture> MakeImageTexture(int width,
                                                     int height,
                                                     const unsigned char* rgb);

}  // namespace lsds::gen
