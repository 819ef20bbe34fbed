#include "generator/scene/texture.h"

#include <algorithm>
#include <cmath>

#include "libs/imaging/image_codecs.h"
#include "libs/util/error.h"
#include "libs/util/srgb.h"

namespace lsds::gen {
namespace {

// OpenCV's BGR(A) image of any depth -> linear RGB texels.
std::shared_ptr<const ImageTexture> FromMat(const cv::Mat& image, const std::string& what) {
  if (image.empty() || image.cols <= 0 || image.rows <= 0)
    throw Error(what + ": cannot read the image");
  cv::Mat rgb;
  const int channels = image.channels();
  auto texture = std::make_shared<ImageTexture>();
  texture->width = image.cols;
  texture->height = image.rows;
  texture->texels.resize(static_cast<size_t>(image.cols) * image.rows);
  const int depth = image.depth();
  const bool encoded = depth == CV_8U || depth == CV_16U;
  const double scale = depth == CV_8U ? 1 / 255.0 : depth == CV_16U ? 1 / 65535.0 : 1.0;
  cv::Mat as_float;
  image.convertTo(as_float, CV_MAKETYPE(CV_32F, channels), scale);
  for (int y = 0; y < image.rows; ++y) {
    const float* row = as_float.ptr<float>(y);
    for (int x = 0; x < image.cols; ++x) {
      const float* px = row + static_cast<size_t>(x) * channels;
      // Grey images repeat their one channel; colour ones are BGR(A).
      Eigen::Vector3f c =
          channels >= 3 ? Eigen::Vector3f(px[2], px[1], px[0]) : Eigen::Vector3f::Constant(px[0]);
      if (encoded)
        for (int a = 0; a < 3; ++a) c[a] = LinearFromSrgb(c[a]);
      texture->texels[static_cast<size_t>(y) * image.cols + x] = c;
    }
  }
  return texture;
}

}  // namespace

Eigen::Vector3f ImageTexture::Sample(const Eigen::Vector2f& uv) const {
  if (texels.empty()) return Eigen::Vector3f::Ones();
  // Texel centres at half-integers; row 0 is v = 1.
  const double fx = static_cast<double>(uv.x()) * width - 0.5;
  const double fy = (1.0 - static_cast<double>(uv.y())) * height - 0.5;
  if (!std::isfinite(fx) || !std::isfinite(fy)) return texels.front();
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  const float tx = static_cast<float>(fx - x0), ty = static_cast<float>(fy - y0);
  auto wrap = [](double i, int n) {
    const double m = std::fmod(i, static_cast<double>(n));
    return static_cast<int>(m < 0 ? m + n : m);
  };
  const int xa = wrap(x0, width), xb = wrap(x0 + 1, width);
  const int ya = wrap(y0, height), yb = wrap(y0 + 1, height);
  auto at = [this](int x, int y) { return texels[static_cast<size_t>(y) * width + x]; };
  return (1 - ty) * ((1 - tx) * at(xa, ya) + tx * at(xb, ya)) +
         ty * ((1 - tx) * at(xa, yb) + tx * at(xb, yb));
}

std::shared_ptr<const ImageTexture> LoadImageTexture(const std::string& path,
                                                     const std::string& where) {
  const cv::Mat image = imaging::ImRead(path, cv::IMREAD_UNCHANGED | cv::IMREAD_ANYDEPTH);
  if (image.empty()) throw Error(where + ": cannot read the texture image '" + path + "'");
  return FromMat(image, where + ": texture '" + path + "'");
}

std::shared_ptr<const ImageTexture> DecodeImageTexture(const unsigned char* bytes,
                                                       size_t size,
                                                       const std::string& where) {
  const cv::Mat buffer(1, static_cast<int>(size), CV_8U, const_cast<unsigned char*>(bytes));
  const cv::Mat image = imaging::ImDecode(buffer, cv::IMREAD_UNCHANGED | cv::IMREAD_ANYDEPTH);
  if (image.empty()) throw Error(where + ": cannot decode the embedded texture image");
  return FromMat(image, where + ": embedded texture");
}

std::shared_ptr<const ImageTexture> MakeImageTexture(int width,
                                                     int height,
                                                     const unsigned char* rgb) {
  cv::Mat bgr(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const unsigned char* p = rgb + 3 * (static_cast<size_t>(y) * width + x);
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(p[2], p[1], p[0]);
    }
  return FromMat(bgr, "texture");
}

}  // namespace lsds::gen
