#include "generator/cycles/cycles_frame.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;

// Cycles writes the background's depth as 1e10.
constexpr float kCyclesSkyDepth = 1e9f;

// The channel of a multilayer EXR whose name ends with `suffix` ("Depth.Z" of
// "ViewLayer.Depth.Z").
const exr::FlatChannel& ChannelEndingWith(const exr::FlatImage& image,
                                          const std::string& suffix,
                                          const fs::path& file) {
  for (const exr::FlatChannel& c : image.channels()) {
    if (c.name == suffix ||
        (c.name.size() > suffix.size() &&
         c.name.compare(c.name.size() - suffix.size() - 1, suffix.size() + 1, "." + suffix) == 0))
      return c;
  }
  throw Error("Cycles' output has no " + suffix + " pass", Location(file.string()));
}

void CheckSize(const exr::FlatImage& image, const Film& film, const fs::path& file) {
  const exr::FlatImage& rgb = film.flat.at("rgb");
  if (image.width() != rgb.width() || image.height() != rgb.height())
    throw Error("Cycles rendered " + std::to_string(image.width()) + "x" +
                    std::to_string(image.height()) + ", the frame is " +
                    std::to_string(rgb.width()) + "x" + std::to_string(rgb.height()),
                Location(file.string()));
}

// Whether the depth at pixel `p` changes by at most kSmoothDepthStep (relative) to each of its
// 4 neighbours. Cycles casts each pixel's first sample, which its data passes come from, through
// the pixel's centre as its pixel filter's table maps it: within about 0.01 px, which at a
// silhouette or on ground seen at a grazing angle (near the horizon the depth changes by the
// pixel's own depth over a few pixels) changes the depth by far more than the renderers differ;
// on smooth pixels it moves it by at most 0.01 * 0.05. Both renderers' depths must be smooth: a
// feature thinner than a pixel (a leaf seen edge-on, a grass blade) can cover one renderer's
// sample and miss the other's, and then only that renderer sees a step.
constexpr double kSmoothDepthStep = 0.05;

// Calls `use` with the depth of each of pixel `p`'s 4 neighbours inside the image.
template <typename Use>
void ForEachNeighbourDepth(const std::vector<float>& depth, int width, size_t p, Use use) {
  const auto height = static_cast<int>(depth.size() / static_cast<size_t>(width));
  const int x = static_cast<int>(p % static_cast<size_t>(width));
  const int y = static_cast<int>(p / static_cast<size_t>(width));
  for (const auto& [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
    const int nx = x + dx, ny = y + dy;
    if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
    use(static_cast<double>(depth[static_cast<size_t>(ny) * width + nx]));
  }
}

bool Smooth(const std::vector<float>& depth, int width, size_t p) {
  const double z = depth[p];
  bool smooth = true;
  ForEachNeighbourDepth(depth, width, p, [&](double n) {
    if (!(std::abs(n - z) <= kSmoothDepthStep * z)) smooth = false;
  });
  return smooth;
}

// How far `z` lies outside the depths lsds saw at pixel `p` and its 4 neighbours. A step smaller
// than kSmoothDepthStep (a wheel's rim proud of its tyre) can pass between the pixel's centre and
// Cycles' sample; Cycles then sees the surface a neighbour sees, not a different geometry.
double OutsideNeighbourhood(const std::vector<float>& depth, int width, size_t p, double z) {
  double low = depth[p], high = depth[p];
  ForEachNeighbourDepth(depth, width, p, [&](double n) {
    low = std::min(low, n);
    high = std::max(high, n);
  });
  return z < low ? low - z : (z > high ? z - high : 0.0);
}

}  // namespace

fs::path CyclesRgbPath(const fs::path& folder, int64_t index) {
  return folder / (FrameStem(index) + "_rgb.exr");
}

CyclesAgreement CompareWithCycles(const fs::path& cycles_exr,
                                  const Film& film,
                                  const std::vector<ExportedNode>& nodes,
                                  const PinholeCamera& camera,
                                  DepthKind depth_kind,
                                  int64_t frame) {
  const exr::FlatImage cycles = exr::ReadFlatExr(cycles_exr);
  CheckSize(cycles, film, cycles_exr);
  const std::vector<float>& cycles_depth = ChannelEndingWith(cycles, "Depth.Z", cycles_exr).floats;
  const std::vector<float>& cycles_index =
      ChannelEndingWith(cycles, "IndexOB.X", cycles_exr).floats;
  const std::vector<float>& depth = film.flat.at("depth").Get("Z").floats;
  const std::vector<uint32_t>& instance = film.flat.at("instanceid").Get("id").uints;
  std::map<int, uint32_t> instance_of_pass = {{0, 0}};
  for (const ExportedNode& n : nodes) instance_of_pass[n.pass_index] = n.instance_id;

  CyclesAgreement agreement;
  agreement.frame = frame;
  agreement.pixels = static_cast<int64_t>(depth.size());
  const int width = cycles.width();
  for (size_t p = 0; p < depth.size(); ++p) {
    const auto pass = static_cast<int>(std::lround(cycles_index[p]));
    const auto found = instance_of_pass.find(pass);
    const bool cycles_sky = !(cycles_depth[p] < kCyclesSkyDepth);
    const bool lsds_sky = !std::isfinite(depth[p]);
    if (found == instance_of_pass.end() || found->second != instance[p] || cycles_sky != lsds_sky) {
      ++agreement.id_mismatches;
      continue;
    }
    if (lsds_sky || !Smooth(depth, width, p) || !Smooth(cycles_depth, width, p)) continue;
    ++agreement.depth_pixels;
    double z = cycles_depth[p];  // planar
    if (depth_kind == DepthKind::kPerspective) {
      const size_t column = p % static_cast<size_t>(width), row = p / static_cast<size_t>(width);
      z = PerspectiveFromPlanarDepth(
          camera, {static_cast<double>(column) + 0.5, static_cast<double>(row) + 0.5}, z);
    }
    const double error =
        OutsideNeighbourhood(depth, width, p, z) / std::max(1e-9, static_cast<double>(depth[p]));
    agreement.max_relative_depth_error = std::max(agreement.max_relative_depth_error, error);
  }
  return agreement;
}

void UseCyclesRgb(const fs::path& rgb_exr, Film* film) {
  const exr::FlatImage cycles = exr::ReadFlatExr(rgb_exr);
  CheckSize(cycles, *film, rgb_exr);
  exr::FlatImage& rgb = film->flat.at("rgb");
  for (const char* c : {"R", "G", "B"}) {
    const std::vector<float>& from = ChannelEndingWith(cycles, c, rgb_exr).floats;
    std::vector<float>& to = rgb.Get(c).floats;
    std::copy(from.begin(), from.end(), to.begin());
  }
}

nlohmann::json AgreementToJson(const CyclesAgreement& a) {
  return {{"frame", a.frame},
          {"pixels", a.pixels},
          {"depth_pixels", a.depth_pixels},
          {"id_mismatches", a.id_mismatches},
          {"max_relative_depth_error", a.max_relative_depth_error}};
}

CyclesAgreement AgreementFromJson(const nlohmann::json& json) {
  CyclesAgreement a;
  a.frame = json.at("frame").get<int64_t>();
  a.pixels = json.at("pixels").get<int64_t>();
  a.depth_pixels = json.at("depth_pixels").get<int64_t>();
  a.id_mismatches = json.at("id_mismatches").get<int64_t>();
  a.max_relative_depth_error = json.at("max_relative_depth_error").get<double>();
  return a;
}

nlohmann::json AgreementSummaryJson(const std::vector<CyclesAgreement>& frames) {
  CyclesAgreement worst_depth, worst_id;
  int64_t pixels = 0, mismatches = 0, depth_pixels = 0;
  for (const CyclesAgreement& a : frames) {
    pixels += a.pixels;
    depth_pixels += a.depth_pixels;
    mismatches += a.id_mismatches;
    if (a.max_relative_depth_error > worst_depth.max_relative_depth_error) worst_depth = a;
    if (a.IdMismatchShare() > worst_id.IdMismatchShare()) worst_id = a;
  }
  return {{"frames", frames.size()},
          {"pixels", pixels},
          {"id_mismatches", mismatches},
          {"depth_pixels", depth_pixels},
          {"max_relative_depth_error", worst_depth.max_relative_depth_error},
          {"max_relative_depth_error_frame", worst_depth.frame},
          {"max_id_mismatch_share", worst_id.IdMismatchShare()},
          {"max_id_mismatch_share_frame", worst_id.frame},
          {"id_mismatch_share",
           pixels > 0 ? static_cast<double>(mismatches) / static_cast<double>(pixels) : 0.0}};
}

}  // namespace lsds::gen
