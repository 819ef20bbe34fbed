#include "generator/render/integrator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "generator/render/pixel_field.h"
#include "generator/render/ray_casts.h"
#include "generator/render/shading.h"
#include "generator/scene/world_ground.h"
#include "libs/util/error.h"

namespace lsds::gen {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Pixels per side of the block whose camera and shadow rays are cast together:
// 2 x 2 pixels at 4 samples are one 16-lane packet (ray_casts.h).
constexpr int kBlock = 2;

struct Hit {
  bool hit = false;
  unsigned geom = 0;
  double t = 0;            // along the ray whose camera-frame direction has z == 1: planar depth
  Eigen::Vector3d point;   // world
  Eigen::Vector3d normal;  // world, unit, facing the camera
  // Interpolated corner normal (smooth shading), on the camera's side; used
  // for lighting only, the normal layer keeps `normal`.
  Eigen::Vector3d shading_normal;
  unsigned prim = 0;  // Embree's triangle and barycentrics: texture lookups
  float u = 0, v = 0;
};

// The plane of the triangle a tile last resolved, for rays from one origin:
// neighbouring samples mostly hit the same triangle, whose unit normal (a
// cross product and a square root) is then computed once. The same doubles
// either way.
struct TrianglePlane {
  unsigned geom = RTC_INVALID_GEOMETRY_ID, prim = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, as the vertices wind
  double offset = 0;                                  // normal . (v0 - origin)
};

// The ray's exact hit: Embree finds the triangle, the plane of its (float)
// vertices gives t in double, so a flat terrain at z = 0 yields z == 0 and
// depth == altitude to double precision.
Hit Resolve(const RenderScene& scene,
            const EmbreeHit& rh,
            const Eigen::Vector3d& origin,
            const Eigen::Vector3d& direction,
            TrianglePlane* plane) {
  Hit hit;
  if (rh.geom == RTC_INVALID_GEOMETRY_ID) {
    // Past the world ground's skirt: the plane it settles to
    // (generator/scene/world_ground.h), exact in double.
    if (scene.ground_plane() >= 0 && direction.z() < 0 && origin.z() > kWorldGroundZ) {
      hit.hit = true;
      hit.geom = static_cast<unsigned>(scene.ground_plane());
      hit.t = (kWorldGroundZ - origin.z()) / direction.z();
      hit.point = origin + hit.t * direction;
      hit.point.z() = kWorldGroundZ;
      hit.normal = hit.shading_normal = Eigen::Vector3d::UnitZ();
    }
    return hit;
  }
  hit.hit = true;
  hit.geom = rh.geom;
  hit.prim = rh.prim;
  hit.u = rh.u;
  hit.v = rh.v;
  const Surface& s = scene.surface(rh.geom);
  if (plane->geom != rh.geom || plane->prim != rh.prim) {
    const Eigen::Vector3i& tri = s.triangles[rh.prim];
    const Eigen::Vector3d v0 = s.positions[tri[0]].cast<double>();
    const Eigen::Vector3d v1 = s.positions[tri[1]].cast<double>();
    const Eigen::Vector3d v2 = s.positions[tri[2]].cast<double>();
    const Eigen::Vector3d n = (v1 - v0).cross(v2 - v0);
    const double nn = n.norm();
    plane->geom = rh.geom;
    plane->prim = rh.prim;
    plane->normal = nn > 0 ? Eigen::Vector3d(n / nn) : Eigen::Vector3d(0, 0, 1);
    plane->offset = plane->normal.dot(v0 - origin);
  }
  Eigen::Vector3d n = plane->normal;
  const double nd = n.dot(direction);
  hit.t = std::abs(nd) > 1e-12 ? plane->offset / nd : rh.tfar;
  if (!(hit.t > 0)) hit.t = rh.tfar;
  if (nd > 0) n = -n;
  hit.normal = n;
  hit.point = origin + hit.t * direction;
  hit.shading_normal = n;
  if (s.corner_normals != nullptr) {
    const Eigen::Vector3f* c = s.corner_normals + 3 * static_cast<size_t>(rh.prim);
    const float u = rh.u, v = rh.v;
    const Eigen::Vector3d smooth = ((1 - u - v) * c[0] + u * c[1] + v * c[2]).cast<double>();
    const double len = smooth.norm();
    if (len > 0) hit.shading_normal = (smooth.dot(n) < 0 ? -smooth : smooth) / len;
  }
  return hit;
}

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
  const int width = camera.width, height = camera.height, spp = settings.sampler.spp;
  Film::Reshape(width, height, spp, settings.bundle, out);
  Film& film = *out;
  const Eigen::Matrix3d world_from_cam =
      frame.cam_from_world.rotation.conjugate().toRotationMatrix();
  const Eigen::Vector3d centre = CameraCenterInWorld(frame.cam_from_world);

  auto ch = [&film](const std::string& layer, const std::string& channel) {
    return &film.flat.at(layer).Get(channel);
  };
  float* rgb[3] = {
      ch("rgb", "R")->floats.data(), ch("rgb", "G")->floats.data(), ch("rgb", "B")->floats.data()};
  uint32_t* class_id = ch("classid", "id")->uints.data();
  uint32_t* instance_id = ch("instanceid", "id")->uints.data();
  float* depth = ch("depth", "Z")->floats.data();
  float* normal[3] = {ch("normal", "X")->floats.data(),
                      ch("normal", "Y")->floats.data(),
                      ch("normal", "Z")->floats.data()};
  float* position[3] = {ch("worldposition", "X")->floats.data(),
                        ch("worldposition", "Y")->floats.data(),
                        ch("worldposition", "Z")->floats.data()};
  float* shadow = ch("shadow", "Y")->floats.data();
  float* motion[2] = {ch("motion", "X")->floats.data(), ch("motion", "Y")->floats.data()};
  // The bundle is written only when the capture asks for it (null: skip).
  exr::DeepImage& bundle = film.bundle;
  const bool with_bundle = settings.bundle;
  auto u = [&](const char* c) { return with_bundle ? bundle.Get(c).uints.data() : nullptr; };
  auto f = [&](const char* c) { return with_bundle ? bundle.Get(c).floats.data() : nullptr; };
  uint32_t* b_instance = u("instanceid");
  uint32_t* b_class = u("classid");
  float* b_z = f("Z");
  float* b_n[3] = {f("NX"), f("NY"), f("NZ")};
  float* b_s[2] = {f("SX"), f("SY")};

  // Motion: the previous camera's centre, where disocclusion rays start.
  const Eigen::Vector3d previous_centre = previous.frame != nullptr
                                              ? CameraCenterInWorld(previous.frame->cam_from_world)
                                              : Eigen::Vector3d::Zero();
  // Smooth fields once per pixel (PixelField), or at every sample.
  const bool reuse = settings.reuse_smooth_fields;
  std::atomic<uint64_t> total_rays{0};
  const int tile = settings.tile_size;
  tbb::parallel_for(
      // Over blocks, so that a block is always the same pixels.
      tbb::blocked_range2d<int>(0,
                                (height + kBlock - 1) / kBlock,
                                std::max(1, tile / kBlock),
                                0,
                                (width + kBlock - 1) / kBlock,
                                std::max(1, tile / kBlock)),
      [&](const tbb::blocked_range2d<int>& r) {
        RTCIntersectContext context;
        InitCoherentContext(&context);
        // A block of up to kBlock x kBlock pixels casts its rays together.
        const int block_rays = kBlock * kBlock * spp;
        std::vector<Eigen::Vector2d> samples(block_rays);
        std::vector<Eigen::Vector3d> rays_in_cam(block_rays), directions(block_rays);
        std::vector<EmbreeHit> embree_hits(block_rays);
        std::vector<Hit> hits(block_rays);
        std::vector<double> cos_suns(block_rays);
        std::vector<Eigen::Vector3d> shadow_origins(block_rays);
        std::vector<uint8_t> facing_sun(block_rays), occluded(block_rays);
        // Per pixel of the block: its disocclusion ray (DisocclusionRay).
        Eigen::Vector3d to_before[kBlock * kBlock];
        float length_to_before[kBlock * kBlock];
        uint8_t test_before[kBlock * kBlock], hidden_before[kBlock * kBlock];
        TrianglePlane plane;
        PixelField<Eigen::Vector3f> albedo_field(Eigen::Vector3f::Zero());
        PixelField<float> cloud_field(0.f);
        uint64_t rays = 0;
        for (int block_row = r.rows().begin(); block_row < r.rows().end(); ++block_row) {
          for (int block_col = r.cols().begin(); block_col < r.cols().end(); ++block_col) {
            // The block's pixels (fewer at the image's edge), row by row.
            int block_x[kBlock * kBlock], block_y[kBlock * kBlock];
            int pixels = 0;
            const int y0 = block_row * kBlock, x0 = block_col * kBlock;
            for (int y = y0; y < std::min(y0 + kBlock, height); ++y) {
              for (int x = x0; x < std::min(x0 + kBlock, width); ++x) {
                block_x[pixels] = x;
                block_y[pixels] = y;
                ++pixels;
              }
            }
            // Pixel p's samples are block rays p * spp to (p + 1) * spp - 1.
            const int count = pixels * spp;
            for (int p = 0; p < pixels; ++p)
              PixelSamples(
                  settings.sampler, frame.index, block_x[p], block_y[p], &samples[p * spp]);
            for (int i = 0; i < count; ++i) {
              rays_in_cam[i] = camera.CamFromImage(samples[i]);  // z == 1
              directions[i] = world_from_cam * rays_in_cam[i];
            }
            if (settings.packets) {
              TraceRays(
                  scene.scene(), centre, directions.data(), count, &context, embree_hits.data());
            } else {
              for (int i = 0; i < count; ++i)
                embree_hits[i] = TraceOne(scene.scene(), centre, directions[i], &context);
            }
            rays += count;
            // The shadow rays of the samples that face the sun, again the
            // block's together.
            for (int i = 0; i < count; ++i) {
              hits[i] = Resolve(scene, embree_hits[i], centre, directions[i], &plane);
              const Hit& hit = hits[i];
              cos_suns[i] = hit.hit ? hit.shading_normal.dot(sky.to_sun()) : 0;
              facing_sun[i] = cos_suns[i] > 0;
              if (!facing_sun[i]) continue;
              shadow_origins[i] = hit.point + hit.normal * (1e-3 * (1.0 + 1e-3 * hit.point.norm()));
              ++rays;
            }
            if (settings.packets) {
              OccludedRays(scene.scene(),
                           shadow_origins.data(),
                           sky.to_sun(),
                           facing_sun.data(),
                           count,
                           &context,
                           occluded.data());
            } else {
              for (int i = 0; i < count; ++i)
                occluded[i] = facing_sun[i] &&
                              Occluded(scene.scene(), shadow_origins[i], sky.to_sun(), &context);
            }
            for (int p = 0; p < pixels; ++p) {
              const int x = block_x[p], y = block_y[p];
              test_before[p] = 0;
              const size_t pixel = static_cast<size_t>(y) * width + x;
              Eigen::Vector3f sum = Eigen::Vector3f::Zero();
              albedo_field.Reset();
              cloud_field.Reset();
              for (int k = 0; k < spp; ++k) {
                const int i = p * spp + k;  // in the block
                const Eigen::Vector3d& ray_in_cam = rays_in_cam[i];
                const Eigen::Vector3d& direction = directions[i];
                const Hit& hit = hits[i];
                Eigen::Vector3f radiance;
                float shadow_ratio = 1.f;
                const size_t b = static_cast<size_t>(pixel) * spp + k;
                double z_value = kInf;
                uint32_t sample_instance = 0, sample_class = 0;
                Eigen::Vector3f sample_normal = Eigen::Vector3f::Zero();
                if (!hit.hit) {
                  radiance = sky.Radiance(direction.normalized());
                } else {
                  const Surface& s = scene.surface(hit.geom);
                  // (Not value_or: the procedural albedo only where no map applies.)
                  const std::optional<Eigen::Vector3f> mapped =
                      s.MappedAlbedo(hit.prim, hit.u, hit.v);
                  const Eigen::Vector3f albedo =
                      mapped ? *mapped : albedo_field.At(hit.geom, hit.point, [&] {
                        return FieldValue<Eigen::Vector3f>{
                            Albedo(*s.material, sky.texture_noise(), hit.point.cast<float>()),
                            reuse ? AlbedoReuseDistance(*s.material) : 0};
                      });
                  const double cos_sun = cos_suns[i];
                  const float lit = !facing_sun[i] || occluded[i]
                                        ? 0.f
                                        : cloud_field.At(hit.geom, hit.point, [&] {
                                            FieldValue<float> lit;
                                            lit.value = static_cast<float>(sky.CloudTransmittance(
                                                hit.point, &lit.reuse_distance));
                                            if (!reuse) lit.reuse_distance = 0;
                                            return lit;
                                          });
                  const Eigen::Vector3f direct =
                      sky.sun_irradiance() * static_cast<float>(std::max(0.0, cos_sun));
                  const Eigen::Vector3f unshadowed = sky.ambient() + direct;
                  const Eigen::Vector3f shaded = sky.ambient() + direct * lit;
                  const float denominator = Luminance(unshadowed);
                  shadow_ratio =
                      denominator > 0 ? std::clamp(Luminance(shaded) / denominator, 0.f, 1.f) : 1.f;
                  radiance =
                      Shade(*s.material, albedo, hit.shading_normal, direction, sky, shaded, lit);
                  const double distance = hit.t * ray_in_cam.norm();
                  if (sky.fog_density() > 0) {
                    const float f = static_cast<float>(std::exp(-sky.fog_density() * distance));
                    radiance = radiance * f + sky.horizon() * (1 - f);
                  }
                  z_value = settings.depth_kind == DepthKind::kPlanar ? hit.t : distance;
                  sample_instance = s.instance_id;
                  sample_class = s.class_id;
                  sample_normal = hit.normal.cast<float>();
                }
                if (with_bundle) {
                  b_s[0][b] = static_cast<float>(samples[i].x() - x);  // [0, 1)
                  b_s[1][b] = static_cast<float>(samples[i].y() - y);
                  b_instance[b] = sample_instance;
                  b_class[b] = sample_class;
                  for (int a = 0; a < 3; ++a) b_n[a][b] = sample_normal[a];
                  b_z[b] = static_cast<float>(z_value);
                }
                sum += radiance;
                if (k != 0) continue;
                // The flat truth layers: the single, non-mixed value of the
                // centre sample.
                film.centre_sample[pixel] = samples[i].cast<float>();
                class_id[pixel] = sample_class;
                instance_id[pixel] = sample_instance;
                depth[pixel] = static_cast<float>(z_value);
                shadow[pixel] = shadow_ratio;
                for (int a = 0; a < 3; ++a) {
                  normal[a][pixel] = sample_normal[a];
                  position[a][pixel] = hit.hit ? static_cast<float>(hit.point[a]) : kInf;
                }
                // No previous frame in the shot: no valid motion.
                Eigen::Vector2d m(kNaN, kNaN);
                if (previous.frame != nullptr && settings.motion) {
                  const PlannedFrame& previous_frame = *previous.frame;
                  if (!hit.hit) {
                    const Eigen::Vector3d dir_prev =
                        previous_frame.cam_from_world.rotation * direction;
                    m = Motion(camera, samples[i], previous_frame.camera, dir_prev);
                  } else {
                    Eigen::Vector3d point_before = hit.point;
                    const int object = scene.surface(hit.geom).object;
                    if (object >= 0 && previous.world != nullptr) {
                      const ObjectState& now = scene.world().objects[object];
                      const ObjectState& before = previous.world->objects[object];
                      point_before = before.WorldFromUnit(now.UnitFromWorld(hit.point));
                    }
                    m = Motion(camera,
                               samples[i],
                               previous_frame.camera,
                               previous_frame.cam_from_world * point_before);
                    // Cast with the block's others below.
                    test_before[p] =
                        std::isfinite(m.x()) && previous.scene != nullptr &&
                        DisocclusionRay(
                            previous_centre, point_before, &to_before[p], &length_to_before[p]);
                    ++rays;
                  }
                }
                motion[0][pixel] = static_cast<float>(m.x());
                motion[1][pixel] = static_cast<float>(m.y());
              }
              sum /= static_cast<float>(spp);
              for (int a = 0; a < 3; ++a) rgb[a][pixel] = sum[a];
            }
            // The block's disocclusion rays: a point the previous camera did
            // not see has no motion.
            if (std::find(test_before, test_before + pixels, 1) != test_before + pixels) {
              if (settings.packets) {
                OccludedSegments(previous.scene->scene(),
                                 previous_centre,
                                 to_before,
                                 length_to_before,
                                 test_before,
                                 pixels,
                                 &context,
                                 hidden_before);
              } else {
                for (int p = 0; p < pixels; ++p)
                  hidden_before[p] = test_before[p] && Occluded(previous.scene->scene(),
                                                                previous_centre,
                                                                to_before[p],
                                                                &context,
                                                                length_to_before[p]);
              }
              for (int p = 0; p < pixels; ++p) {
                if (!hidden_before[p]) continue;
                const size_t pixel = static_cast<size_t>(block_y[p]) * width + block_x[p];
                motion[0][pixel] = motion[1][pixel] = kNaN;
              }
            }
          }
        }
        total_rays += rays;
      });
  film.rays = total_rays;
}

}  // namespace lsds::gen
