#include "generator/render/integrator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "generator/render/exact_hit.h"
#include "generator/render/pixel_field.h"
#include "generator/render/ray_casts.h"
#include "generator/render/shading.h"
#include "generator/scene/ground_detail.h"
#include "libs/util/counter_rng.h"
#include "libs/util/error.h"

namespace lsds::gen {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Sky light (docs/generator.md, "Light from the whole sky"): a pixel's
// surface sees the sky through kSkyRays cosine-weighted rays, each blocked
// within kSkyOcclusionM or not; the draws are counter-based (field
// kSkyLightField), so a pixel's rays are the same in every run.
constexpr int kSkyRays = 4;
constexpr double kSkyOcclusionM = 30;
constexpr uint64_t kSkyLightField = 0x5c71;
// Two pixels of a block share their sky rays (FrameRenderer::BlockSkyLight)
// when they see the same surface with shading normals within about 25 degrees
// and points within 4 pixel footprints.
constexpr double kSkyAlikeCos = 0.9;
constexpr double kSkyAlikeFootprints = 4;

float Luminance(const Eigen::Vector3f& c) {
  return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z();
}

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Screen-normalized motion (Unreal's convention) of a point seen now at
// `pixel_now` that the previous camera saw at `point_in_previous_cam`; NaN
// (no valid motion, docs/format.md "Motion") when the point was behind that
// camera or outside its image.
Eigen::Vector2d Motion(const PinholeCamera& camera,
                       const Eigen::Vector2d& pixel_now,
                       const PinholeCamera& previous_camera,
                       const Eigen::Vector3d& point_in_previous_cam) {
  Eigen::Vector2d invalid(kNaN, kNaN);
  if (!(point_in_previous_cam.z() > 1e-9)) return invalid;
  const Eigen::Vector2d before = previous_camera.ImageFromCam(point_in_previous_cam);
  if (!(before.x() >= 0 && before.x() < previous_camera.width && before.y() >= 0 &&
        before.y() < previous_camera.height))
    return invalid;
  return {0.5 + 0.5 * (pixel_now.x() - before.x()) / camera.width,
          0.5 + 0.5 * (pixel_now.y() - before.y()) / camera.height};
}

// Where RenderFrame writes: the film's channels as plain arrays. The bundle's
// are null when the film has no bundle.
struct FilmTargets {
  float* rgb[3];
  uint32_t* class_id;
  uint32_t* instance_id;
  float* depth;
  float* normal[3];
  float* position[3];
  float* shadow;
  float* motion[2];
  Eigen::Vector2f* centre_sample;
  uint32_t* bundle_instance = nullptr;
  uint32_t* bundle_class = nullptr;
  float* bundle_z = nullptr;
  float* bundle_normal[3] = {nullptr, nullptr, nullptr};
  float* bundle_position[2] = {nullptr, nullptr};  // SX, SY

  FilmTargets(Film* film, bool with_bundle) {
    auto flat = [film](const char* layer, const char* channel) {
      return &film->flat.at(layer).Get(channel);
    };
    for (int a = 0; a < 3; ++a) {
      rgb[a] = flat("rgb", std::string(1, "RGB"[a]).c_str())->floats.data();
      normal[a] = flat("normal", std::string(1, "XYZ"[a]).c_str())->floats.data();
      position[a] = flat("worldposition", std::string(1, "XYZ"[a]).c_str())->floats.data();
    }
    class_id = flat("classid", "id")->uints.data();
    instance_id = flat("instanceid", "id")->uints.data();
    depth = flat("depth", "Z")->floats.data();
    shadow = flat("shadow", "Y")->floats.data();
    motion[0] = flat("motion", "X")->floats.data();
    motion[1] = flat("motion", "Y")->floats.data();
    centre_sample = film->centre_sample.data();
    if (!with_bundle) return;
    exr::DeepImage& bundle = film->bundle;
    bundle_instance = bundle.Get("instanceid").uints.data();
    bundle_class = bundle.Get("classid").uints.data();
    bundle_z = bundle.Get("Z").floats.data();
    bundle_normal[0] = bundle.Get("NX").floats.data();
    bundle_normal[1] = bundle.Get("NY").floats.data();
    bundle_normal[2] = bundle.Get("NZ").floats.data();
    bundle_position[0] = bundle.Get("SX").floats.data();
    bundle_position[1] = bundle.Get("SY").floats.data();
  }
};

// The samples of a block of pixels (ray_casts.h, kBlock), their rays and
// hits; pixel p's samples are block rays p * spp to (p + 1) * spp - 1.
struct BlockRays {
  explicit BlockRays(int spp)
      : samples(static_cast<size_t>(kBlock * kBlock) * spp),
        rays_in_cam(samples.size()),
        directions(samples.size()),
        embree_hits(samples.size()),
        hits(samples.size()),
        cos_suns(samples.size()),
        shadow_origins(samples.size()),
        facing_sun(samples.size()),
        occluded(samples.size()) {}

  int pixels = 0;
  int x[kBlock * kBlock], y[kBlock * kBlock];
  std::vector<Eigen::Vector2d> samples;      // image coordinates
  std::vector<Eigen::Vector3d> rays_in_cam;  // z == 1
  std::vector<Eigen::Vector3d> directions;   // world
  std::vector<EmbreeHit> embree_hits;
  std::vector<ExactHit> hits;
  std::vector<double> cos_suns;  // shading normal . to the sun
  std::vector<Eigen::Vector3d> shadow_origins;
  std::vector<uint8_t> facing_sun, occluded;
  // Each pixel's sky light (FrameRenderer::BlockSkyLight), where it hit a surface.
  Eigen::Vector3f sky_light[kBlock * kBlock];
};

// A block's disocclusion rays (DisocclusionRay), one per pixel.
struct BlockDisocclusions {
  Eigen::Vector3d direction[kBlock * kBlock];
  float length[kBlock * kBlock];
  uint8_t test[kBlock * kBlock];
  uint8_t hidden[kBlock * kBlock];
};

// A procedural surface at a point: its albedo and the detail's tilt of the
// shading normal (generator/scene/ground_detail.h).
struct SurfaceTexture {
  Eigen::Vector3f albedo = Eigen::Vector3f::Zero();
  Eigen::Vector2f tilt = Eigen::Vector2f::Zero();
};

// The smooth fields a task keeps while it shades: the albedo and cloud shadow
// of the pixel (reset per pixel), the cloud shadow's last exactly constant
// stretch (kept across pixels), and the pixel's horizon colour.
struct ShadingFields {
  PixelField<SurfaceTexture> albedo{SurfaceTexture{}};
  PixelField<float> cloud{0.f};
  ExactBall<float> exact_cloud;
  std::optional<Eigen::Vector3f> haze;  // the pixel's horizon colour
};

// What one sample contributes: its radiance and its values of the truth
// layers (sky: infinite depth, ids 0, normal 0).
struct SampleValue {
  Eigen::Vector3f radiance;
  float shadow_ratio = 1.f;
  double z = kInf;
  uint32_t instance = 0, class_id = 0;
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
};

// How a pixel's centre sample was shaded, for the pixel's other samples that
// take its radiance (RenderSettings::shade_pixels_once): the smooth fields as
// the centre left them (a later sample may replace the pixel's own), and the
// radiance.
struct CentreShading {
  PixelField<SurfaceTexture> albedo;
  PixelField<float> cloud;
  Eigen::Vector3f radiance;
};

// One frame being rendered: what every block needs, and the steps of a block.
class FrameRenderer {
 public:
  FrameRenderer(const RenderScene& scene,
                const Sky& sky,
                const PlannedFrame& frame,
                const PreviousView& previous,
                const RenderSettings& settings,
                Film* film)
      : scene_(scene),
        sky_(sky),
        frame_(frame),
        previous_(previous),
        settings_(settings),
        spp_(settings.sampler.spp),
        sampler_(settings.sampler, frame.index),
        with_motion_(previous.frame != nullptr && settings.motion),
        world_from_cam_(frame.cam_from_world.rotation.conjugate().toRotationMatrix()),
        centre_(CameraCenterInWorld(frame.cam_from_world)),
        previous_centre_(previous.frame != nullptr
                             ? CameraCenterInWorld(previous.frame->cam_from_world)
                             : Eigen::Vector3d::Zero()),
        film_(film, settings.bundle) {}

  // The samples of block (block_row, block_col), their camera rays and, for
  // the hits that face the sun, their shadow rays: each kind as packets.
  void CastBlock(int block_row,
                 int block_col,
                 BlockRays* block,
                 TrianglePlane* plane,
                 RTCIntersectContext* context,
                 uint64_t* rays) const {
    const PinholeCamera& camera = frame_.camera;
    block->pixels =
        BlockPixels(block_row, block_col, camera.width, camera.height, block->x, block->y);
    const int count = block->pixels * spp_;
    for (int p = 0; p < block->pixels; ++p)
      sampler_.PixelSamples(
          block->x[p], block->y[p], &block->samples[static_cast<size_t>(p) * spp_]);
    for (int i = 0; i < count; ++i) {
      block->rays_in_cam[i] = camera.CamFromImage(block->samples[i]);
      block->directions[i] = world_from_cam_ * block->rays_in_cam[i];
    }
    if (settings_.packets) {
      TraceRays(scene_.scene(),
                centre_,
                block->directions.data(),
                count,
                context,
                block->embree_hits.data());
    } else {
      for (int i = 0; i < count; ++i)
        block->embree_hits[i] = TraceOne(scene_.scene(), centre_, block->directions[i], context);
    }
    *rays += count;
    for (int i = 0; i < count; ++i) {
      block->hits[i] =
          ResolveExactHit(scene_, block->embree_hits[i], centre_, block->directions[i], plane);
      const ExactHit& hit = block->hits[i];
      block->cos_suns[i] = hit.hit ? hit.shading_normal.dot(sky_.to_sun()) : 0;
      // Truth only: the shadow layer is the centre sample's (sample 0 of its pixel).
      block->facing_sun[i] = block->cos_suns[i] > 0 && (settings_.shade_rgb || i % spp_ == 0);
      if (!block->facing_sun[i]) continue;
      block->shadow_origins[i] = hit.point + hit.normal * (1e-3 * (1.0 + 1e-3 * hit.point.norm()));
      ++*rays;
    }
    if (settings_.packets) {
      OccludedRays(scene_.scene(),
                   block->shadow_origins.data(),
                   sky_.to_sun(),
                   block->facing_sun.data(),
                   count,
                   context,
                   block->occluded.data());
    } else {
      for (int i = 0; i < count; ++i)
        block->occluded[i] =
            block->facing_sun[i] &&
            Occluded(scene_.scene(), block->shadow_origins[i], sky_.to_sun(), context);
    }
  }

  // The light of the sky on each pixel's surface (irradiance / pi, as
  // Sky::ambient()), at the pixel's first sample that hits a surface, into
  // block->sky_light: cosine-weighted rays about the shading normal; one
  // that reaches the open sky brings the sky's light, one heading below the
  // horizon the light open ground reflects (Sky::ground_bounce()), one
  // blocked within kSkyOcclusionM the light a shaded blocker reflects
  // (Sky::blocker_bounce()). Open flat ground sees the whole sky: exactly
  // Sky::ambient(), the level the shadow layer is defined on.
  //
  // The block's pixels whose surfaces are alike (SkyAlike) share their rays:
  // a pixel casts kSkyRays / (its alike pixels, itself included) of them,
  // rounded up, and takes the mean of every ray its alike pixels cast. Open
  // ground thus casts one ray per pixel and still sees kSkyRays; a pixel alone
  // in its block (an edge) casts all kSkyRays itself. The rays are one
  // packet.
  void BlockSkyLight(BlockRays* block, RTCIntersectContext* context, uint64_t* rays) const {
    constexpr int kPixels = kBlock * kBlock;
    int first[kPixels];
    for (int p = 0; p < block->pixels; ++p) {
      first[p] = -1;
      for (int k = 0; k < spp_ && first[p] < 0; ++k)
        if (block->hits[p * spp_ + k].hit) first[p] = p * spp_ + k;
    }
    bool alike[kPixels][kPixels];
    int group[kPixels];
    for (int p = 0; p < block->pixels; ++p) {
      group[p] = 0;
      for (int q = 0; q < block->pixels; ++q) {
        alike[p][q] =
            first[p] >= 0 && first[q] >= 0 && (p == q || SkyAlike(*block, first[p], first[q]));
        group[p] += alike[p][q];
      }
    }
    constexpr int kMaxRays = kPixels * kSkyRays;
    Eigen::Vector3d origins[kMaxRays], directions[kMaxRays];
    float lengths[kMaxRays];
    uint8_t wanted[kMaxRays], blocked[kMaxRays];
    int owner[kMaxRays];
    bool ground[kMaxRays];
    int count = 0;
    for (int p = 0; p < block->pixels; ++p) {
      if (first[p] < 0) continue;
      const ExactHit& hit = block->hits[first[p]];
      const size_t pixel = static_cast<size_t>(block->y[p]) * frame_.camera.width + block->x[p];
      const Eigen::Vector3d& n = hit.shading_normal;
      Eigen::Vector3d t1, t2;
      TangentFrame(n, &t1, &t2);
      const Eigen::Vector3d origin =
          hit.point + hit.normal * (1e-3 * (1.0 + 1e-3 * hit.point.norm()));
      const int own = (kSkyRays + group[p] - 1) / group[p];
      for (int j = 0; j < own; ++j) {
        // Stratified over the 2x2 cells of the unit square (the block's
        // pixels start at different cells), then mapped to the
        // cosine-weighted hemisphere (Malley's method).
        const int cell = (p + j) % kSkyRays;
        const int row = cell / 2;  // the cell's column is cell % 2
        const double cell_u = cell % 2, cell_v = row;
        const uint64_t draw = 2 * (static_cast<uint64_t>(pixel) * kSkyRays + cell);
        const double u1 = (cell_u + Uniform01(kSkyLightField, 0, frame_.index, draw)) / 2;
        const double u2 = (cell_v + Uniform01(kSkyLightField, 0, frame_.index, draw + 1)) / 2;
        const double r = std::sqrt(u1), phi = 2 * M_PI * u2;
        const Eigen::Vector3d d =
            r * std::cos(phi) * t1 + r * std::sin(phi) * t2 + std::sqrt(1 - u1) * n;
        origins[count] = origin;
        directions[count] = d;
        lengths[count] = static_cast<float>(kSkyOcclusionM);
        owner[count] = p;
        // Into the surface itself: blocked; below the horizon: open ground.
        ground[count] = d.dot(hit.normal) > 0 && d.z() <= 0;
        wanted[count] = d.dot(hit.normal) > 0 && d.z() > 0;
        *rays += wanted[count];
        ++count;
      }
    }
    if (count == 0) return;
    OccludedSegments(scene_.scene(), origins, directions, lengths, wanted, count, context, blocked);
    for (int p = 0; p < block->pixels; ++p) {
      if (first[p] < 0) continue;
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      int n = 0;
      for (int k = 0; k < count; ++k) {
        if (!alike[p][owner[k]]) continue;
        sum += wanted[k] && !blocked[k] ? sky_.ambient()
               : ground[k]              ? sky_.ground_bounce()
                                        : sky_.blocker_bounce();
        ++n;
      }
      block->sky_light[p] = sum / static_cast<float>(n);
    }
  }

  // Pixel p of the block: its RGB (the mean of its samples' radiance), its
  // bundle samples, and its flat truth layers (the centre sample's values).
  // Its motion waits for the block's disocclusion rays (`disocclusions`).
  void RenderPixel(const BlockRays& block,
                   int p,
                   ShadingFields* fields,
                   BlockDisocclusions* disocclusions,
                   uint64_t* rays) const {
    const int x = block.x[p], y = block.y[p];
    const size_t pixel = static_cast<size_t>(y) * frame_.camera.width + x;
    fields->albedo.Reset();
    fields->cloud.Reset();
    fields->haze.reset();
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    const int c = p * spp_;  // the centre sample, in the block
    std::optional<CentreShading> centre;
    for (int k = 0; k < spp_; ++k) {
      const int i = c + k;  // in the block
      SampleValue v;
      if (!settings_.shade_rgb) {
        v = k == 0 ? CentreTruth(block, i, fields) : SampleTruth(block, i);
        v.radiance.setZero();
      } else if (centre && ShadesAsCentre(block, c, i, *centre)) {
        v = SampleTruth(block, i);
        v.radiance = centre->radiance;
      } else {
        v = ShadeSample(block, i, p, fields);
      }
      if (k == 0 && settings_.shade_pixels_once)
        centre = CentreShading{fields->albedo, fields->cloud, v.radiance};
      sum += v.radiance;
      if (film_.bundle_z != nullptr) {
        const size_t b = pixel * spp_ + k;
        film_.bundle_position[0][b] = static_cast<float>(block.samples[i].x() - x);  // [0, 1)
        film_.bundle_position[1][b] = static_cast<float>(block.samples[i].y() - y);
        film_.bundle_instance[b] = v.instance;
        film_.bundle_class[b] = v.class_id;
        for (int a = 0; a < 3; ++a) film_.bundle_normal[a][b] = v.normal[a];
        film_.bundle_z[b] = static_cast<float>(v.z);
      }
      if (k != 0) continue;
      // The flat truth layers: the single, non-mixed value of the centre
      // sample.
      const ExactHit& hit = block.hits[i];
      film_.centre_sample[pixel] = block.samples[i].cast<float>();
      film_.class_id[pixel] = v.class_id;
      film_.instance_id[pixel] = v.instance;
      film_.depth[pixel] = static_cast<float>(v.z);
      film_.shadow[pixel] = v.shadow_ratio;
      for (int a = 0; a < 3; ++a) {
        film_.normal[a][pixel] = v.normal[a];
        film_.position[a][pixel] = hit.hit ? static_cast<float>(hit.point[a]) : kInf;
      }
      const Eigen::Vector2d m = CentreMotion(block, i, disocclusions, p, rays);
      film_.motion[0][pixel] = static_cast<float>(m.x());
      film_.motion[1][pixel] = static_cast<float>(m.y());
    }
    sum /= static_cast<float>(spp_);
    for (int a = 0; a < 3; ++a) film_.rgb[a][pixel] = sum[a];
  }

  // The block's disocclusion rays, as one packet: a point the previous camera
  // did not see has no motion.
  void DropDisoccludedMotion(const BlockRays& block,
                             BlockDisocclusions* d,
                             RTCIntersectContext* context) const {
    if (std::find(d->test, d->test + block.pixels, 1) == d->test + block.pixels) return;
    if (settings_.packets) {
      OccludedSegments(previous_.scene->scene(),
                       previous_centre_,
                       d->direction,
                       d->length,
                       d->test,
                       block.pixels,
                       context,
                       d->hidden);
    } else {
      for (int p = 0; p < block.pixels; ++p)
        d->hidden[p] =
            d->test[p] &&
            Occluded(
                previous_.scene->scene(), previous_centre_, d->direction[p], context, d->length[p]);
    }
    for (int p = 0; p < block.pixels; ++p) {
      if (!d->hidden[p]) continue;
      const size_t pixel = static_cast<size_t>(block.y[p]) * frame_.camera.width + block.x[p];
      film_.motion[0][pixel] = film_.motion[1][pixel] = kNaN;
    }
  }

 private:
  // The distance from the camera to block sample i's hit.
  double Distance(const BlockRays& block, int i) const {
    return block.hits[i].t * block.rays_in_cam[i].norm();
  }

  // Block sample i's values of the truth layers, without its radiance.
  SampleValue SampleTruth(const BlockRays& block, int i) const {
    const ExactHit& hit = block.hits[i];
    SampleValue v;
    if (!hit.hit) return v;
    const Surface& s = scene_.surface(hit.geom);
    v.z = settings_.depth_kind == DepthKind::kPlanar ? hit.t : Distance(block, i);
    v.instance = s.instance_id;
    v.class_id = s.class_id;
    v.normal = hit.normal.cast<float>();
    return v;
  }

  // Block sample i's truth values with its shadow ratio (the shadow layer's, as ShadeSample
  // computes it), without shading it: RenderSettings::shade_rgb off.
  SampleValue CentreTruth(const BlockRays& block, int i, ShadingFields* fields) const {
    SampleValue v = SampleTruth(block, i);
    if (!block.hits[i].hit) return v;
    const float lit =
        !block.facing_sun[i] || block.occluded[i] ? 0.f : CloudShadow(block.hits[i], fields);
    const Eigen::Vector3f direct =
        sky_.sun_irradiance() * static_cast<float>(std::max(0.0, block.cos_suns[i]));
    const float denominator = Luminance(sky_.ambient() + direct);
    v.shadow_ratio =
        denominator > 0
            ? std::clamp(Luminance(sky_.ambient() + direct * lit) / denominator, 0.f, 1.f)
            : 1.f;
    return v;
  }

  // Whether block sample i takes the radiance of its pixel's centre sample c
  // (RenderSettings::shade_pixels_once). On a diffuse surface the radiance is
  // albedo x (ambient + sun x cos x cloud), seen through the fog: the sample
  // must hit the centre's triangle within the reuse distances of the
  // centre's procedural albedo (so never where an image texture applies: the
  // centre then evaluated none) and cloud shadow, in or out of the sun as the
  // centre is, with its cosine to the sun and its fog within
  // kShadeOnceTolerance of the centre's.
  bool ShadesAsCentre(const BlockRays& block, int c, int i, const CentreShading& centre) const {
    const ExactHit& hit = block.hits[i];
    const ExactHit& centre_hit = block.hits[c];
    if (!hit.hit || !centre_hit.hit || hit.geom != centre_hit.geom || hit.prim != centre_hit.prim) {
      return false;
    }
    const Surface& s = scene_.surface(hit.geom);
    if (s.material->specular > 0 || !centre.albedo.Holds(hit.geom, hit.point)) return false;
    // Ground detail is shared by the pixel's samples (ShadeSample), which are
    // still shaded each: its reuse over a whole footprint would let the cloud
    // shadow's history-dependent reuse decide which samples take the
    // centre's radiance, and the films would depend on the tiles.
    if (s.material->detail.contrast > 0 && settings_.ground_detail) return false;
    const bool sunlit = block.facing_sun[i] && !block.occluded[i];
    if (sunlit != (block.facing_sun[c] && !block.occluded[c])) return false;
    if (sunlit && (!centre.cloud.Holds(hit.geom, hit.point) ||
                   std::abs(block.cos_suns[i] - block.cos_suns[c]) >
                       kShadeOnceTolerance * block.cos_suns[c])) {
      return false;
    }
    return sky_.extinction() * std::abs(Distance(block, i) - Distance(block, c)) <=
           kShadeOnceTolerance;
  }

  // Whether block samples i and j (two pixels' first surface samples) see
  // alike skies: the same surface, shading normals within kSkyAlikeCos, and
  // points within kSkyAlikeFootprints pixel footprints.
  bool SkyAlike(const BlockRays& block, int i, int j) const {
    const ExactHit& a = block.hits[i];
    const ExactHit& b = block.hits[j];
    if (a.geom != b.geom || a.shading_normal.dot(b.shading_normal) < kSkyAlikeCos) return false;
    const double footprint = std::max(Footprint(block, i), Footprint(block, j));
    return (a.point - b.point).norm() <= kSkyAlikeFootprints * footprint;
  }

  // Block sample i's pixel footprint on its surface (m).
  double Footprint(const BlockRays& block, int i) const {
    return Distance(block, i) / frame_.camera.fx /
           std::max(0.1, std::abs(block.hits[i].normal.dot(block.directions[i].normalized())));
  }

  // Block sample i of pixel p: the sky, or the shaded surface it hits (the
  // procedural albedo and the cloud shadow through the pixel's fields).
  SampleValue ShadeSample(const BlockRays& block, int i, int p, ShadingFields* fields) const {
    const Eigen::Vector3d& direction = block.directions[i];
    const ExactHit& hit = block.hits[i];
    SampleValue v = SampleTruth(block, i);
    if (!hit.hit) {
      v.radiance = sky_.Radiance(direction.normalized());
      return v;
    }
    const bool reuse = settings_.reuse_smooth_fields;
    const Surface& s = scene_.surface(hit.geom);
    // The pixel's footprint on the surface (m), which decides the finest
    // ground detail it shows (none when the detail is off: an infinite
    // footprint).
    const float footprint =
        settings_.ground_detail ? static_cast<float>(Footprint(block, i)) : kInf;
    // (Not value_or: the procedural albedo only where no map applies.)
    const std::optional<Eigen::Vector3f> mapped = s.MappedAlbedo(hit.prim, hit.u, hit.v);
    const SurfaceTexture texture =
        mapped ? SurfaceTexture{*mapped, Eigen::Vector2f::Zero()}
               : fields->albedo.At(hit.geom, hit.point, [&] {
                   SurfaceTexture t;
                   // The terrain is a height field: its detail is 2D noise.
                   t.albedo = Albedo(*s.material,
                                     sky_.texture_noise(),
                                     hit.point.cast<float>(),
                                     footprint,
                                     &t.tilt,
                                     s.object < 0);
                   // Ground detail is sampled once per pixel, as a texture at
                   // its mip level: the pixel's samples within a footprint of
                   // this one take its value.
                   const double detail_reuse =
                       s.material->detail.contrast > 0 && settings_.ground_detail ? footprint : 0;
                   return FieldValue<SurfaceTexture>{
                       t,
                       reuse ? std::max(AlbedoReuseDistance(*s.material, footprint), detail_reuse)
                             : 0};
                 });
    const float lit = !block.facing_sun[i] || block.occluded[i] ? 0.f : CloudShadow(hit, fields);
    // The shadow layer (truth): the sun on the shading normal against the
    // plan's ambient light.
    const Eigen::Vector3f direct =
        sky_.sun_irradiance() * static_cast<float>(std::max(0.0, block.cos_suns[i]));
    const Eigen::Vector3f unshadowed = sky_.ambient() + direct;
    const Eigen::Vector3f shaded = sky_.ambient() + direct * lit;
    const float denominator = Luminance(unshadowed);
    v.shadow_ratio = denominator > 0 ? std::clamp(Luminance(shaded) / denominator, 0.f, 1.f) : 1.f;
    // The rgb: the sun on the detail's tilted normal, and the sky this
    // pixel's surface sees.
    const Eigen::Vector3d normal = TiltedNormal(hit.shading_normal, texture.tilt);
    const Eigen::Vector3f irradiance =
        block.sky_light[p] +
        sky_.sun_irradiance() * static_cast<float>(std::max(0.0, normal.dot(sky_.to_sun()))) * lit;
    v.radiance = Shade(*s.material, texture.albedo, normal, direction, sky_, irradiance, lit);
    // Haze: fog and the air's own extinction, towards the sky's horizon in
    // this azimuth, which the farthest ground then meets without a seam.
    const float f = static_cast<float>(sky_.HazeTransmittance(Distance(block, i)));
    if (f < 1) {
      if (!fields->haze) fields->haze = sky_.Haze(direction);  // once per pixel
      v.radiance = v.radiance * f + *fields->haze * (1 - f);
    }
    return v;
  }

  // The share of sunlight through the clouds at a hit facing the sun: the
  // pixel's value where it applies (PixelField); else, inside the task's last
  // clear or full stretch of the deck (ExactBall), the bits a fresh evaluation
  // gives, without the noise; else evaluated.
  float CloudShadow(const ExactHit& hit, ShadingFields* fields) const {
    const bool reuse = settings_.reuse_smooth_fields;
    return fields->cloud.At(hit.geom, hit.point, [&] {
      FieldValue<float> lit;
      double remaining = 0, exact = 0;
      if (reuse && fields->exact_cloud.Find(hit.point, &lit.value, &remaining)) {
        lit.reuse_distance = sky_.CloudReuseDistanceInside(hit.point, remaining);
        return lit;
      }
      lit.value =
          static_cast<float>(sky_.CloudTransmittance(hit.point, &lit.reuse_distance, &exact));
      if (!reuse) {
        lit.reuse_distance = 0;  // per sample
        return lit;
      }
      fields->exact_cloud.Keep(hit.point, lit.value, exact);
      return lit;
    });
  }

  // The motion of block sample i, pixel p's centre sample, against the
  // previous frame (NaN without one). A surface point the previous camera
  // saw in its image also gets a disocclusion ray in `disocclusions`.
  Eigen::Vector2d CentreMotion(const BlockRays& block,
                               int i,
                               BlockDisocclusions* disocclusions,
                               int p,
                               uint64_t* rays) const {
    disocclusions->test[p] = 0;
    if (!with_motion_) return {kNaN, kNaN};
    const PlannedFrame& previous_frame = *previous_.frame;
    const ExactHit& hit = block.hits[i];
    const Eigen::Vector2d& sample = block.samples[i];
    if (!hit.hit) {
      const Eigen::Vector3d dir_prev = previous_frame.cam_from_world.rotation * block.directions[i];
      return Motion(frame_.camera, sample, previous_frame.camera, dir_prev);
    }
    Eigen::Vector3d point_before = hit.point;
    const int object = scene_.surface(hit.geom).object;
    if (object >= 0 && previous_.world != nullptr) {
      const ObjectState& now = scene_.world().objects[object];
      const ObjectState& before = previous_.world->objects[object];
      point_before = before.WorldFromUnit(now.UnitFromWorld(hit.point));
    }
    Eigen::Vector2d m = Motion(
        frame_.camera, sample, previous_frame.camera, previous_frame.cam_from_world * point_before);
    disocclusions->test[p] = std::isfinite(m.x()) && previous_.scene != nullptr &&
                             DisocclusionRay(previous_centre_,
                                             point_before,
                                             &disocclusions->direction[p],
                                             &disocclusions->length[p]);
    ++*rays;
    return m;
  }

  const RenderScene& scene_;
  const Sky& sky_;
  const PlannedFrame& frame_;
  const PreviousView& previous_;
  const RenderSettings& settings_;
  const int spp_;
  const FrameSampler sampler_;
  const bool with_motion_;
  const Eigen::Matrix3d world_from_cam_;
  const Eigen::Vector3d centre_, previous_centre_;
  FilmTargets film_;
};

}  // namespace

Film RenderFrame(const RenderScene& scene,
                 const Sky& sky,
                 const PlannedFrame& frame,
                 const PreviousView& previous,
                 const RenderSettings& settings) {
  Film film;
  RenderFrame(scene, sky, frame, previous, settings, &film);
  return film;
}

void RenderFrame(const RenderScene& scene,
                 const Sky& sky,
                 const PlannedFrame& frame,
                 const PreviousView& previous,
                 const RenderSettings& settings,
                 Film* out) {
  CheckSamplerSettings(settings.sampler);
  const PinholeCamera& camera = frame.camera;
  if (camera.width <= 0 || camera.height <= 0 || !(camera.fx > 0) || !(camera.fy > 0)) {
    throw Error("frame " + std::to_string(frame.index) + ": the camera has no valid intrinsics");
  }
  Film::Reshape(camera.width, camera.height, settings.sampler.spp, settings.bundle, out);
  const FrameRenderer renderer(scene, sky, frame, previous, settings, out);
  std::atomic<uint64_t> total_rays{0};
  // Tiles of whole blocks (a block is always the same pixels). A task's
  // smooth fields carry over from pixel to pixel, and which of them a sample
  // reuses decides its last bits: the simple partitioner cuts the frame into
  // the same tiles whatever the threads and their timing, so a frame's bits
  // depend only on its tiles, never on the run.
  const int tile = std::max(1, settings.tile_size / kBlock);
  tbb::parallel_for(
      tbb::blocked_range2d<int>(0,
                                (camera.height + kBlock - 1) / kBlock,
                                tile,
                                0,
                                (camera.width + kBlock - 1) / kBlock,
                                tile),
      [&](const tbb::blocked_range2d<int>& r) {
        RTCIntersectContext context;
        InitCoherentContext(&context);
        BlockRays block(settings.sampler.spp);
        BlockDisocclusions disocclusions;
        TrianglePlane plane;
        ShadingFields fields;
        uint64_t rays = 0;
        for (int row = r.rows().begin(); row < r.rows().end(); ++row) {
          for (int col = r.cols().begin(); col < r.cols().end(); ++col) {
            renderer.CastBlock(row, col, &block, &plane, &context, &rays);
            if (settings.shade_rgb) renderer.BlockSkyLight(&block, &context, &rays);
            for (int p = 0; p < block.pixels; ++p)
              renderer.RenderPixel(block, p, &fields, &disocclusions, &rays);
            renderer.DropDisoccludedMotion(block, &disocclusions, &context);
          }
        }
        total_rays += rays;
      },
      tbb::simple_partitioner());
  out->rays = total_rays;
}

}  // namespace lsds::gen
