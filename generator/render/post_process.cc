#include "generator/render/post_process.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "libs/imaging/image_codecs.h"
#include "libs/util/counter_rng.h"
#include "libs/util/strings.h"

namespace lsds::gen {
namespace {

std::string Key(const std::string& name) {
  std::string out;
  for (char c : name)
    if (c != '_' && c != '-' && c != ' ')
      out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// The rgb layer as one 3-channel float image (R, G, B order) and back.
cv::Mat ReadRgb(const Film& film) {
  const exr::FlatImage& rgb = film.flat.at("rgb");
  cv::Mat out(rgb.height(), rgb.width(), CV_32FC3);
  const float* c[3] = {
      rgb.Get("R").floats.data(), rgb.Get("G").floats.data(), rgb.Get("B").floats.data()};
  for (int y = 0; y < rgb.height(); ++y)
    for (int x = 0; x < rgb.width(); ++x) {
      const size_t p = static_cast<size_t>(y) * rgb.width() + x;
      out.at<cv::Vec3f>(y, x) = cv::Vec3f(c[0][p], c[1][p], c[2][p]);
    }
  return out;
}

void WriteRgb(const cv::Mat& image, Film* film) {
  exr::FlatImage& rgb = film->flat.at("rgb");
  float* c[3] = {
      rgb.Get("R").floats.data(), rgb.Get("G").floats.data(), rgb.Get("B").floats.data()};
  for (int y = 0; y < rgb.height(); ++y)
    for (int x = 0; x < rgb.width(); ++x) {
      const size_t p = static_cast<size_t>(y) * rgb.width() + x;
      const cv::Vec3f v = image.at<cv::Vec3f>(y, x);
      for (int a = 0; a < 3; ++a) c[a][p] = v[a];
    }
}

// Edge blur: a lens that is not perfectly sharp and a sensor that integrates
// over the pixel soften silhouettes. Pixels whose 3x3 neighbourhood changes
// instance or depth by more than 5 % get a Gaussian (sigma 0.8 px) of their
// neighbourhood; flat interiors are kept sharp.
void EdgeBlur(const Film& film, cv::Mat* image) {
  const exr::FlatImage& ids = film.flat.at("instanceid");
  const std::vector<uint32_t>& id = ids.Get("id").uints;
  const std::vector<float>& z = film.flat.at("depth").Get("Z").floats;
  const int w = ids.width(), h = ids.height();
  cv::Mat blurred;
  cv::GaussianBlur(*image, blurred, cv::Size(5, 5), 0.8, 0.8, cv::BORDER_REFLECT);
  cv::Mat out = image->clone();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y) * w + x;
      bool edge = false;
      for (int dy = -1; dy <= 1 && !edge; ++dy)
        for (int dx = -1; dx <= 1 && !edge; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u < 0 || v < 0 || u >= w || v >= h) continue;
          const size_t q = static_cast<size_t>(v) * w + u;
          // An edge: another instance, sky against surface, or a depth step over 5 %.
          edge = id[q] != id[p] || std::isfinite(z[p]) != std::isfinite(z[q]) ||
                 (std::isfinite(z[p]) && std::abs(z[q] - z[p]) > 0.05f * std::min(z[p], z[q]));
        }
      if (edge) out.at<cv::Vec3f>(y, x) = blurred.at<cv::Vec3f>(y, x);
    }
  *image = out;
}

// Motion blur along each pixel's own motion vector (the motion layer: where
// the surface was in the previous frame), over half the frame interval (a
// 180-degree shutter), 8 taps; no blur where motion is NaN.
void MotionBlur(const Film& film, cv::Mat* image) {
  const exr::FlatImage& motion = film.flat.at("motion");
  const std::vector<float>& mx = motion.Get("X").floats;
  const std::vector<float>& my = motion.Get("Y").floats;
  const int w = motion.width(), h = motion.height();
  cv::Mat out = image->clone();
  constexpr int kTaps = 8;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y) * w + x;
      if (!std::isfinite(mx[p]) || !std::isfinite(my[p])) continue;
      // Pixels moved since the previous frame (docs/format.md "Motion").
      const float vx = (mx[p] - 0.5f) * 2 * w, vy = (my[p] - 0.5f) * 2 * h;
      if (std::abs(vx) + std::abs(vy) < 0.25f) continue;
      cv::Vec3f sum(0, 0, 0);
      for (int k = 0; k < kTaps; ++k) {
        const float s = 0.5f * k / (kTaps - 1);  // back along the path, half the interval
        const int u = std::clamp(static_cast<int>(std::lround(x - s * vx)), 0, w - 1);
        const int v = std::clamp(static_cast<int>(std::lround(y - s * vy)), 0, h - 1);
        sum += image->at<cv::Vec3f>(v, u);
      }
      out.at<cv::Vec3f>(y, x) = sum / kTaps;
    }
  *image = out;
}

// Sensor noise: photon shot noise (variance proportional to the signal) plus
// read noise, relative to the frame's mean level so that it looks the same at
// any light level. Draws from the one counter RNG, by (seed, frame, pixel).
void SensorNoise(uint64_t seed, int64_t frame, cv::Mat* image) {
  const cv::Scalar mean = cv::mean(*image);
  const double level = std::max(1e-6, (mean[0] + mean[1] + mean[2]) / 3);
  const double shot = 0.01 * level, read = 0.005 * level;  // per unit signal, absolute
  uint64_t draw = 0;
  for (int y = 0; y < image->rows; ++y)
    for (int x = 0; x < image->cols; ++x) {
      cv::Vec3f& v = image->at<cv::Vec3f>(y, x);
      for (int a = 0; a < 3; ++a) {
        const double sigma = std::sqrt(shot * std::max(0.f, v[a]) + read * read);
        const double n = StandardNormal(seed, 0x5e7, static_cast<uint64_t>(frame), draw++);
        v[a] = static_cast<float>(std::max(0.0, v[a] + sigma * n));
      }
    }
}

// Vignetting: the natural cos^4 falloff of the angle off the optical axis.
void Vignetting(const PinholeCamera& camera, cv::Mat* image) {
  for (int y = 0; y < image->rows; ++y)
    for (int x = 0; x < image->cols; ++x) {
      const Eigen::Vector3d r = camera.RayThroughPixelCenter(x, y);
      const double c = 1.0 / r.norm();  // cos of the angle, r.z == 1
      image->at<cv::Vec3f>(y, x) *= static_cast<float>(c * c * c * c);
    }
}

// JPEG compression: the frame is scaled so that its 99th-percentile value is
// white, sRGB encoded, JPEG compressed at quality 75 (OpenCV) and decoded back
// to linear; the part of a value above white is kept, so highlights survive.
void JpegCompression(cv::Mat* image) {
  std::vector<float> values(image->begin<float>(), image->begin<float>() + image->total() * 3);
  const size_t k = values.size() * 99 / 100;
  std::nth_element(values.begin(), values.begin() + k, values.end());
  const float white = std::max(1e-6f, values[k]);
  auto encode = [](float v) {
    v = std::clamp(v, 0.f, 1.f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f;
  };
  auto decode = [](float s) {
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
  };
  cv::Mat bgr(image->rows, image->cols, CV_8UC3);
  for (int y = 0; y < image->rows; ++y)
    for (int x = 0; x < image->cols; ++x) {
      const cv::Vec3f v = image->at<cv::Vec3f>(y, x) / white;
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uint8_t>(std::lround(255 * encode(v[2]))),
                                          static_cast<uint8_t>(std::lround(255 * encode(v[1]))),
                                          static_cast<uint8_t>(std::lround(255 * encode(v[0]))));
    }
  std::vector<uint8_t> bytes;
  imaging::ImEncode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, 75});
  const cv::Mat decoded = imaging::ImDecode(bytes, cv::IMREAD_COLOR);
  for (int y = 0; y < image->rows; ++y)
    for (int x = 0; x < image->cols; ++x) {
      cv::Vec3f& v = image->at<cv::Vec3f>(y, x);
      const cv::Vec3b d = decoded.at<cv::Vec3b>(y, x);
      for (int a = 0; a < 3; ++a) {
        const float excess = std::max(0.f, v[a] - white);
        v[a] = white * decode(d[2 - a] / 255.f) + excess;
      }
    }
}

// Cartoon style (the paper's example): colours posterized to 6 levels per
// channel in display space and silhouettes (instance or depth edges) drawn
// dark.
void CartoonStyle(const Film& film, cv::Mat* image) {
  const cv::Scalar mean = cv::mean(*image);
  const float level = static_cast<float>(std::max(1e-6, (mean[0] + mean[1] + mean[2]) / 3));
  for (auto it = image->begin<cv::Vec3f>(); it != image->end<cv::Vec3f>(); ++it)
    for (int a = 0; a < 3; ++a) {
      const float s = std::sqrt(std::max(0.f, (*it)[a] / (4 * level)));  // display-like
      const float q = std::round(std::min(s, 1.5f) * 5) / 5;
      (*it)[a] = q * q * 4 * level;
    }
  const std::vector<uint32_t>& id = film.flat.at("instanceid").Get("id").uints;
  const int w = image->cols, h = image->rows;
  for (int y = 0; y + 1 < h; ++y)
    for (int x = 0; x + 1 < w; ++x) {
      const size_t p = static_cast<size_t>(y) * w + x;
      if (id[p] != id[p + 1] || id[p] != id[p + w]) image->at<cv::Vec3f>(y, x) *= 0.1f;
    }
}

// Depth of field by the thin-lens model: a point at depth z, with the lens of focal length f at
// f-number N focused at s, images as a disc of diameter c = f^2 / (N (s - f)) |z - s| / z on the
// sensor. f comes from fx and the sensor width (36 mm, full frame, unless given), N from the
// exposure (8 by default), s from `focus_distance` (else the depth at the centre pixel, an
// autofocus). Each pixel takes the colour of the image blurred by its own disc, interpolated
// between discs of 0, 1, 2, 4, 8 and 16 px (a disc over 16 px is 16 px). Where nothing was hit
// (the sky) is at infinity. Returns the distance focused at.
double DepthOfField(const Film& film,
                    const PlannedFrame& frame,
                    const PlannedExposure& lens,
                    cv::Mat* image) {
  const std::vector<float>& z = film.flat.at("depth").Get("Z").floats;
  const int w = image->cols, h = image->rows;
  double focus = lens.focus_distance_m.value_or(0);
  if (!(focus > 0)) {
    const float centre = z[static_cast<size_t>(h / 2) * w + w / 2];
    focus = std::isfinite(centre) && centre > 0 ? centre : 1e9;
  }
  const double pitch_m = lens.sensor_width_mm.value_or(36) * 1e-3 / frame.camera.width;
  const double f_m = frame.camera.fx * pitch_m;
  const double n = lens.f_number.value_or(8);
  // The disc in pixels per unit of |z - s| / z.
  const double disc_px = f_m * f_m / (n * std::max(focus - f_m, 1e-6)) / pitch_m;
  static constexpr double kRadii[] = {0, 1, 2, 4, 8, 16};  // disc diameters, px
  std::vector<cv::Mat> levels;
  for (const double d : kRadii) {
    if (d == 0) {
      levels.push_back(*image);
      continue;
    }
    cv::Mat blurred;
    const int size = 2 * static_cast<int>(std::ceil(d)) + 1;
    cv::GaussianBlur(*image, blurred, cv::Size(size, size), d / 2.355 * 1.0, 0, cv::BORDER_REFLECT);
    levels.push_back(blurred);
  }
  cv::Mat out(image->size(), CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float depth = z[static_cast<size_t>(y) * w + x];
      const double off = std::isfinite(depth) && depth > 0 ? std::abs(depth - focus) / depth : 1.0;
      const double d = std::min(disc_px * off, 16.0);
      size_t i = 0;
      while (i + 2 < std::size(kRadii) && kRadii[i + 1] < d) ++i;
      const double t = std::clamp((d - kRadii[i]) / (kRadii[i + 1] - kRadii[i]), 0.0, 1.0);
      out.at<cv::Vec3f>(y, x) = levels[i].at<cv::Vec3f>(y, x) * static_cast<float>(1 - t) +
                                levels[i + 1].at<cv::Vec3f>(y, x) * static_cast<float>(t);
    }
  *image = out;
  return focus;
}

struct Effect {
  const char* name;
  std::vector<const char*> aliases;
};
const std::vector<Effect>& Effects() {
  static const std::vector<Effect> effects = {
      {"EdgeBlur", {"defocus", "lensblur"}},
      {"MotionBlur", {}},
      {"SensorNoise", {"noise"}},
      {"Vignetting", {"vignette"}},
      {"JpegCompression", {"jpeg", "jpg"}},
      {"CartoonStyle", {"cartoon"}},
      {"DepthOfField", {"dof", "bokeh"}},
  };
  return effects;
}

}  // namespace

const std::vector<std::string>& PostProcessNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const Effect& e : Effects()) n.push_back(e.name);
    return n;
  }();
  return names;
}

std::string CanonicalPostProcess(const std::string& name) {
  const std::string key = Key(name);
  for (const Effect& e : Effects()) {
    if (Key(e.name) == key) return e.name;
    for (const char* a : e.aliases)
      if (key == a) return e.name;
  }
  return "";
}

std::vector<std::string> UnknownPostProcess(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const std::string& n : names)
    if (CanonicalPostProcess(n).empty())
      out.push_back("post-process material '" + n + "' is not an effect and is not applied" +
                    DidYouMean(n, PostProcessNames()) +
                    "; known: " + Join(PostProcessNames(), ", "));
  return out;
}

std::optional<double> ApplyPostProcess(const std::vector<std::string>& names,
                                       uint64_t seed,
                                       const PlannedFrame& frame,
                                       const PlannedExposure& lens,
                                       Film* film) {
  std::optional<double> focused;
  if (names.empty()) return focused;
  cv::Mat image = ReadRgb(*film);
  for (const std::string& name : names) {
    const std::string effect = CanonicalPostProcess(name);
    if (effect == "EdgeBlur") EdgeBlur(*film, &image);
    if (effect == "MotionBlur") MotionBlur(*film, &image);
    if (effect == "SensorNoise") SensorNoise(seed, frame.index, &image);
    if (effect == "Vignetting") Vignetting(frame.camera, &image);
    if (effect == "JpegCompression") JpegCompression(&image);
    if (effect == "CartoonStyle") CartoonStyle(*film, &image);
    if (effect == "DepthOfField") focused = DepthOfField(*film, frame, lens, &image);
  }
  WriteRgb(image, film);
  return focused;
}

}  // namespace lsds::gen
