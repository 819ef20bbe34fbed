#include "synth/synthetic_collection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "libs/collection/collection_builder.h"
#include "libs/collection/json_io.h"
#include "libs/collection/object_truth.h"
#include "libs/geometry/attitude.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::synth {

namespace fs = std::filesystem;
using exr::DeepImage;
using exr::FlatImage;
using exr::PixelType;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Whether another surface hid `point` from `centre`: a disoccluded pixel.
bool HiddenFrom(const AnalyticScene& scene,
                const Eigen::Vector3d& centre,
                const Eigen::Vector3d& point) {
  const Eigen::Vector3d d = point - centre;
  const double distance = d.norm();
  const Hit first = scene.Intersect(centre, d / distance);
  return first.hit && first.t < distance - (1e-9 * distance + 1e-9);
}
constexpr double kAmbient = 0.3;

Eigen::Vector3d Albedo(uint32_t class_id) {
  switch (class_id) {
    case 0:
      return {0.5, 0.7, 1.0};  // sky radiance
    case 1:
      return {0.35, 0.3, 0.2};
    case 2:
      return {0.7, 0.2, 0.1};
    case 3:
      return {0.2, 0.5, 0.2};
    default:
      return {0.5, 0.5, 0.5};
  }
}

// Sub-pixel sample positions in [0, 1)^2: strata centres, with the stratum
// holding the pixel centre moved onto it; that sample comes first
// (docs/format.md, "Pixel bundles").
std::vector<Eigen::Vector2d> SamplePattern(int n) {
  std::vector<Eigen::Vector2d> samples = {{0.5, 0.5}};
  const int centre_stratum = n / 2;
  for (int b = 0; b < n; ++b) {
    for (int a = 0; a < n; ++a) {
      if (a == centre_stratum && b == centre_stratum) continue;
      samples.push_back({(a + 0.5) / n, (b + 0.5) / n});
    }
  }
  return samples;
}

struct Sample {
  Hit hit;
  Eigen::Vector3d point = Eigen::Vector3d::Constant(kInf);
  double planar = kInf;
  double perspective = kInf;
  double sun_visibility = 1;
  double shadow = 1;  // final / unshadowed shading
  Eigen::Vector3d radiance = Eigen::Vector3d::Zero();
};

Sample Shade(const AnalyticScene& scene,
             const Spec& spec,
             const PinholeCamera& camera,
             const Rigid3d& world_from_cam,
             const Eigen::Vector2d& pixel) {
  Sample s;
  const Eigen::Vector3d ray_in_cam = camera.CamFromImage(pixel);  // z == 1: t is planar depth
  const Eigen::Vector3d direction = world_from_cam.rotation * ray_in_cam;
  s.hit = scene.Intersect(world_from_cam.translation, direction);
  if (!s.hit.hit) {
    s.radiance = Albedo(0);
    return s;
  }
  s.planar = s.hit.t;
  s.perspective = s.hit.t * ray_in_cam.norm();
  s.point = world_from_cam.translation + s.hit.t * direction;
  const double cosine = s.hit.normal.dot(spec.direction_to_sun);
  if (cosine > 0) {
    const Hit blocker = scene.Intersect(s.point + 1e-6 * s.hit.normal, spec.direction_to_sun);
    s.sun_visibility = blocker.hit ? 0.0 : 1.0;
    s.shadow = (kAmbient + cosine * s.sun_visibility) / (kAmbient + cosine);
  }
  s.radiance = Albedo(s.hit.class_id) * (kAmbient + std::max(0.0, cosine) * s.sun_visibility);
  return s;
}

PinholeCamera Camera(const Spec& spec) {
  return PinholeCamera::FromHorizontalFov(spec.width, spec.height, spec.hfov_deg);
}

}  // namespace

AnalyticScene Spec::Scene() const {
  AnalyticScene scene;
  scene.ground = ground;
  scene.boxes = boxes;
  return scene;
}

std::vector<std::string> Spec::LayerSemantics() const {
  return layers.empty() ? StandardLayerSemantics() : layers;
}

Rigid3d NadirCamFromWorld(const Eigen::Vector3d& position_in_world) {
  // Pitch -90 looks down; with yaw 0 the image x axis is east and the image top
  // is north.
  return CamFromEnu(position_in_world, Attitude{0.0, -90.0, 0.0});
}

Spec DefaultSpec() {
  Spec spec;
  spec.classes = {{1, "ground"}, {2, "box"}, {3, "crate"}};
  Box a;
  a.class_id = 2, a.instance_id = 1, a.name = "box#0";
  a.center = {0, 0, 1}, a.half_extents = {1, 1, 1};
  Box b;
  b.class_id = 2, b.instance_id = 2, b.name = "box#1";
  b.center = {4, 2, 0.5}, b.half_extents = {0.5, 0.5, 0.5}, b.yaw_deg = 30;
  Box c;
  c.class_id = 3, c.instance_id = 3, c.name = "crate#0";
  c.center = {-3, -2, 0.75}, c.half_extents = {1.5, 0.75, 0.75}, c.yaw_deg = -20;
  spec.boxes = {a, b, c};
  for (int k = 0; k < 4; ++k)
    spec.cam_from_world.push_back(NadirCamFromWorld({-1.5 + k, 0.0, 20.0}));
  return spec;
}

Spec CircleSpec(int frames, int width, int height) {
  Spec spec = DefaultSpec();
  spec.width = width;
  spec.height = height;
  spec.cam_from_world.clear();
  for (int k = 0; k < frames; ++k) {
    const double angle = 2.0 * 3.14159265358979323846 * k / std::max(1, frames);
    spec.cam_from_world.push_back(
        NadirCamFromWorld({3.0 * std::cos(angle), 3.0 * std::sin(angle), 20.0}));
  }
  return spec;
}

namespace {

// The stages of RenderFrame: allocate the layers, shade every sample into the bundle and its
// centre sample into the flat layers (with the motion since the previous camera), then
// measure the truth on the rendered id layer.

// What one frame is rendered from.
struct SynthView {
  AnalyticScene scene;
  PinholeCamera camera;
  Rigid3d cam_from_world;
  Rigid3d world_from_cam;
  std::optional<Rigid3d> previous_cam_from_world;
  Eigen::Vector3d previous_centre;  // the previous camera's centre (zero without one)
  int w = 0, h = 0;
};

SynthView ViewOf(const Spec& spec, int frame) {
  SynthView view;
  view.scene = spec.Scene();
  view.camera = Camera(spec);
  view.cam_from_world = spec.cam_from_world.at(frame);
  view.world_from_cam = view.cam_from_world.Inverse();
  view.previous_cam_from_world =
      frame > 0 ? std::optional<Rigid3d>(spec.cam_from_world[frame - 1]) : std::nullopt;
  view.previous_centre = view.previous_cam_from_world
                             ? view.previous_cam_from_world->Inverse().translation
                             : Eigen::Vector3d::Zero();
  view.w = spec.width;
  view.h = spec.height;
  return view;
}

// Every standard layer of a w x h frame with its channels, and the bundle of
// samples_per_pixel samples per pixel.
RenderedFrame AllocateLayers(int w, int h, size_t samples_per_pixel) {
  RenderedFrame out;
  for (const LayerInfo& layer : {StandardLayer("rgb"),
                                 StandardLayer("classid"),
                                 StandardLayer("instanceid"),
                                 StandardLayer("depth"),
                                 StandardLayer("normal"),
                                 StandardLayer("worldposition"),
                                 StandardLayer("shadow"),
                                 StandardLayer("motion")}) {
    FlatImage& image = out.flat[layer.semantic] = FlatImage(w, h);
    for (const LayerChannel& c : layer.channels) image.AddChannel(c.name, c.type);
  }
  out.bundle =
      DeepImage(w, h, std::vector<uint32_t>(static_cast<size_t>(w) * h, samples_per_pixel));
  for (const LayerChannel& c : StandardLayer("bundle").channels)
    out.bundle.AddChannel(c.name, c.type);
  return out;
}

// Channel storage looked up once, not per sample.
struct LayerStorage {
  explicit LayerStorage(RenderedFrame& out)
      : bundle_instance(out.bundle.Get("instanceid").uints.data()),
        bundle_class(out.bundle.Get("classid").uints.data()),
        bundle_depth(out.bundle.Get("Z").floats.data()),
        bundle_normal{out.bundle.Get("NX").floats.data(),
                      out.bundle.Get("NY").floats.data(),
                      out.bundle.Get("NZ").floats.data()},
        bundle_sx(out.bundle.Get("SX").floats.data()),
        bundle_sy(out.bundle.Get("SY").floats.data()),
        rgb{Floats(out, "rgb", "R"), Floats(out, "rgb", "G"), Floats(out, "rgb", "B")},
        class_pixels(out.flat["classid"].Get("id").uints.data()),
        instance_pixels(out.flat["instanceid"].Get("id").uints.data()),
        depth_pixels(Floats(out, "depth", "Z")),
        normal_pixels{
            Floats(out, "normal", "X"), Floats(out, "normal", "Y"), Floats(out, "normal", "Z")},
        position_pixels{Floats(out, "worldposition", "X"),
                        Floats(out, "worldposition", "Y"),
                        Floats(out, "worldposition", "Z")},
        shadow_pixels(Floats(out, "shadow", "Y")),
        motion_pixels{Floats(out, "motion", "X"), Floats(out, "motion", "Y")} {}
  static float* Floats(RenderedFrame& out, const char* semantic, const char* channel) {
    return out.flat[semantic].Get(channel).floats.data();
  }
  uint32_t* bundle_instance;
  uint32_t* bundle_class;
  float* bundle_depth;
  float* bundle_normal[3];
  float* bundle_sx;
  float* bundle_sy;
  float* rgb[3];
  uint32_t* class_pixels;
  uint32_t* instance_pixels;
  float* depth_pixels;
  float* normal_pixels[3];
  float* position_pixels[3];
  float* shadow_pixels;
  float* motion_pixels[2];
};

// Motion against the previous frame (one shot: a static world seen
// by a moving camera); NaN where there is none (docs/format.md).
Eigen::Vector2d MotionShift(const SynthView& view, const Sample& s, const Eigen::Vector2d& at) {
  Eigen::Vector2d shift(kNaN, kNaN);
  if (!view.previous_cam_from_world) return shift;
  // Where this surface point (or, for sky, this direction) was last
  // frame, if that camera saw it.
  const Eigen::Vector3d in_previous =
      s.hit.hit ? Eigen::Vector3d(*view.previous_cam_from_world * s.point)
                : Eigen::Vector3d(view.previous_cam_from_world->rotation *
                                  (view.world_from_cam.rotation * view.camera.CamFromImage(at)));
  if (in_previous.z() > 0) {
    const Eigen::Vector2d before = view.camera.ImageFromCam(in_previous);
    const bool inside =
        before.x() >= 0 && before.x() < view.w && before.y() >= 0 && before.y() < view.h;
    if (inside && !(s.hit.hit && HiddenFrom(view.scene, view.previous_centre, s.point)))
      shift = at - before;
  }
  return shift;
}

// The centre sample is the single value of every truth layer.
void WriteCentreSample(const SynthView& view,
                       const Sample& s,
                       const Eigen::Vector2d& at,
                       size_t p,
                       float depth,
                       const LayerStorage& to) {
  to.class_pixels[p] = s.hit.class_id;
  to.instance_pixels[p] = s.hit.instance_id;
  to.depth_pixels[p] = depth;
  for (int c = 0; c < 3; ++c) {
    to.normal_pixels[c][p] = static_cast<float>(s.hit.normal[c]);
    to.position_pixels[c][p] = s.hit.hit ? static_cast<float>(s.point[c]) : kInf;
  }
  to.shadow_pixels[p] = static_cast<float>(s.shadow);
  const Eigen::Vector2d shift = MotionShift(view, s, at);
  to.motion_pixels[0][p] = static_cast<float>(0.5 + 0.5 * shift.x() / view.w);
  to.motion_pixels[1][p] = static_cast<float>(0.5 + 0.5 * shift.y() / view.h);
}

// Each box's truth, measured on the rendered id layer like the generator's.
void MeasureBoxes(const Spec& spec,
                  const SynthView& view,
                  const FlatImage& instanceid,
                  Frame* truth) {
  const int w = view.w, h = view.h;
  const auto masks = MeasureInstanceMasks(instanceid.Get("id").uints, w, h);
  for (size_t b = 0; b < spec.boxes.size(); ++b) {
    const Box& box = spec.boxes[b];
    ObjectIdentity identity;
    identity.instance_id = box.instance_id;
    identity.class_id = box.class_id;
    identity.name = box.name;
    identity.asset = "box";
    identity.obb = box.Obb();
    const auto mask = masks.find(box.instance_id);
    // The box alone, through the same pixel centres as the id layer.
    auto count_unoccluded = [&](const Box2d& bounds) {
      int64_t unoccluded = 0;
      for (int j = static_cast<int>(bounds.y0); j < static_cast<int>(std::ceil(bounds.y1)); ++j) {
        for (int i = static_cast<int>(bounds.x0); i < static_cast<int>(std::ceil(bounds.x1)); ++i) {
          const Eigen::Vector3d direction =
              view.world_from_cam.rotation * view.camera.RayThroughPixelCenter(i, j);
          if (view.scene
                  .Intersect(view.world_from_cam.translation, direction, 1e-9, static_cast<int>(b))
                  .hit)
            ++unoccluded;
        }
      }
      return unoccluded;
    };
    if (std::optional<ObjectTruth> object =
            MeasureObjectTruth(identity,
                               view.camera,
                               view.cam_from_world,
                               {instanceid.Get("id").uints.data(), w, h},
                               mask == masks.end() ? nullptr : &mask->second,
                               count_unoccluded)) {
      object->transmittance = 1.0;  // no atmosphere
      truth->objects.push_back(std::move(*object));
    }
  }
}

}  // namespace

RenderedFrame RenderFrame(const Spec& spec, int frame) {
  const SynthView view = ViewOf(spec, frame);
  const int w = view.w, h = view.h;
  const std::vector<Eigen::Vector2d> pattern = SamplePattern(spec.samples_per_axis);
  const size_t samples_per_pixel = pattern.size();
  RenderedFrame out = AllocateLayers(w, h, samples_per_pixel);
  const LayerStorage to(out);
  const FlatImage& rgb = out.flat["rgb"];
  const bool planar = spec.depth_kind == DepthKind::kPlanar;

  tbb::parallel_for(0, h, [&](int j) {
    for (int i = 0; i < w; ++i) {
      const size_t p = rgb.Index(i, j);
      Eigen::Vector3d radiance = Eigen::Vector3d::Zero();
      for (size_t k = 0; k < samples_per_pixel; ++k) {
        const Eigen::Vector2d at(i + pattern[k].x(), j + pattern[k].y());
        const Sample s = Shade(view.scene, spec, view.camera, view.world_from_cam, at);
        radiance += s.radiance;
        const uint64_t q = out.bundle.FirstSample(i, j) + k;
        to.bundle_instance[q] = s.hit.instance_id;
        to.bundle_class[q] = s.hit.class_id;
        to.bundle_depth[q] = static_cast<float>(planar ? s.planar : s.perspective);
        for (int c = 0; c < 3; ++c) to.bundle_normal[c][q] = static_cast<float>(s.hit.normal[c]);
        to.bundle_sx[q] = static_cast<float>(pattern[k].x());
        to.bundle_sy[q] = static_cast<float>(pattern[k].y());
        if (k == 0) WriteCentreSample(view, s, at, p, to.bundle_depth[q], to);
      }
      radiance /= static_cast<double>(samples_per_pixel);
      for (int c = 0; c < 3; ++c) to.rgb[c][p] = static_cast<float>(radiance[c]);
    }
  });

  // Truth, measured on the rendered layers.
  Frame& truth = out.truth;
  truth.index = frame;
  truth.time = frame * spec.frame_interval;
  truth.sequence = spec.sequence;
  truth.shot = 0;  // one continuous flight
  truth.camera.intrinsics = view.camera;
  SetCamFromWorld(view.cam_from_world, &truth.camera);
  MeasureBoxes(spec, view, out.flat["instanceid"], &truth);
  return out;
}

void WriteCollection(const fs::path& root, const Spec& spec) {
  std::error_code ec;
  if (fs::exists(root, ec) && !fs::is_empty(root, ec)) {
    throw Error("synthetic collection target exists and is not empty", Location(root.string()));
  }
  fs::create_directories(root);
  const std::vector<std::string> semantics = spec.LayerSemantics();
  CollectionHeader header;
  header.provenance.generator = "lsds synth";
  header.provenance.generator_version = LSDS_VERSION;
  header.provenance.seed = 0;
  header.provenance.render = {{"samples_per_pixel", SamplePattern(spec.samples_per_axis).size()},
                              {"renderer", "analytic ray casting"}};
  header.classes = spec.classes;
  for (const std::string& semantic : semantics) {
    header.layers.push_back(StandardLayer(semantic, spec.depth_kind));
    if (header.layers.back().deep) header.layers.back().layout = spec.bundle_layout;
    fs::create_directories(root / semantic);
  }
  header.metadata = {{kMetadataFile, false, "measured metadata, equal to truth"}};
  header.frame_count = static_cast<int64_t>(spec.cam_from_world.size());

  CollectionBuilder builder(root, header);
  for (int k = 0; k < static_cast<int>(spec.cam_from_world.size()); ++k) {
    RenderedFrame rendered = RenderFrame(spec, k);
    // Centre sample first, then strata centres: jitter 0.
    const int spp = static_cast<int>(SamplePattern(spec.samples_per_axis).size());
    rendered.truth.files = WriteFrameLayers(root,
                                            header,
                                            k,
                                            rendered.truth.camera,
                                            {&rendered.flat,
                                             &rendered.bundle,
                                             BundleSampling{{spp, 0.0, 0}, k, std::nullopt},
                                             std::nullopt});
    builder.Append(rendered.truth);
  }
  builder.Commit();
}

}  // namespace lsds::synth
