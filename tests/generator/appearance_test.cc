// The renderer's appearance (docs/generator.md): the unbounded world (no camera
// sees a void past the terrain's edge), smooth shading that follows the
// surface, not its triangles, while the truth layers keep the exact geometric
// values; cloud shadows the shadow layer accounts for; metals that reflect.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "generator/render/integrator.h"
#include "generator/scene/mesh.h"
#include "generator/scene/smooth_normals.h"
#include "generator/scene/terrain.h"
#include "generator/scene/world_ground.h"
#include "libs/util/counter_rng.h"
#include "tests/generator/test_plans.h"

namespace lsds::gen {
namespace {

Plan HillyPlan(int width, int height) {
  Plan plan = testing::FlatPlan(width, height, 70);
  plan.terrain.size = {120, 120};
  plan.terrain.perlin_amplitude = 4;
  plan.terrain.perlin_frequency = 0.04;
  plan.terrain.perlin_seed = 3;
  plan.frames.clear();
  return plan;
}

void AddFrame(Plan* plan, const Rigid3d& cam_from_world, int width = 64, int height = 48) {
  PlannedFrame f;
  f.index = static_cast<int64_t>(plan->frames.size());
  f.shot = f.index;
  f.camera = PinholeCamera::FromHorizontalFov(width, height, 70);
  f.cam_from_world = cam_from_world;
  plan->frames.push_back(f);
}

// Frame k of `plan` at `spp` samples per pixel (4: as `lsds generate`).
Film RenderK(const Plan& plan, size_t k, int spp = 1) {
  static EmbreeDevice device;
  const SceneAssets assets = BuildSceneAssets(plan);
  const WorldState world = WorldAt(plan, plan.frames[k]);
  const RenderScene scene(device, plan, assets, world);
  RenderSettings settings;
  settings.sampler = {spp, 1.0, plan.seed};
  return RenderFrame(scene, Sky(plan), plan.frames[k], PreviousView(), settings);
}

struct VoidCount {
  size_t pixels = 0;
  size_t past_edge = 0;  // rays that leave the terrain below the horizon: void before
  size_t void_now = 0;   // below the horizon and still no surface
  size_t bad_ids = 0;    // a surface that is neither terrain, world ground nor object
};

VoidCount CountVoid(const Plan& plan) {
  VoidCount c;
  const double hx = plan.terrain.size.x() / 2, hy = plan.terrain.size.y() / 2;
  for (size_t k = 0; k < plan.frames.size(); ++k) {
    const Film film = RenderK(plan, k);
    const PlannedFrame& f = plan.frames[k];
    const Eigen::Matrix3d world_from_cam = f.cam_from_world.rotation.conjugate().toRotationMatrix();
    const auto& depth = film.flat.at("depth").Get("Z").floats;
    const auto& x = film.flat.at("worldposition").Get("X").floats;
    const auto& y = film.flat.at("worldposition").Get("Y").floats;
    const auto& instance = film.flat.at("instanceid").Get("id").uints;
    for (size_t p = 0; p < depth.size(); ++p) {
      ++c.pixels;
      const Eigen::Vector3d d =
          world_from_cam * f.camera.CamFromImage(film.centre_sample[p].cast<double>());
      if (std::isinf(depth[p])) {
        if (d.z() < 0) ++c.void_now, ++c.past_edge;
        continue;
      }
      const bool outside = std::abs(x[p]) > hx || std::abs(y[p]) > hy;
      if (outside) ++c.past_edge;
      if (outside ? instance[p] != 0 : instance[p] != plan.terrain.instance_id) ++c.bad_ids;
    }
  }
  return c;
}

void ExpectNoVoid(const Plan& plan, const char* what, double min_past_edge) {
  const VoidCount c = CountVoid(plan);
  std::printf("%s: %zu frames, void before %.1f %% of pixels, now %.1f %%\n",
              what,
              plan.frames.size(),
              100.0 * c.past_edge / c.pixels,
              100.0 * c.void_now / c.pixels);
  EXPECT_GE(static_cast<double>(c.past_edge) / c.pixels, min_past_edge) << what;
  EXPECT_EQ(c.void_now, 0u) << what;
  EXPECT_EQ(c.bad_ids, 0u) << what;
}

TEST(World, HorizonViewsOverHillsSeeGroundToTheHorizon) {
  Plan plan = HillyPlan(64, 48);
  for (int a = 0; a < 4; ++a) {
    const double az = a * M_PI / 2 + 0.3;
    AddFrame(
        &plan,
        LookAt(
            {0, 0, 30}, {1000 * std::cos(az), 1000 * std::sin(az), 20}, Eigen::Vector3d::UnitZ()));
  }
  ExpectNoVoid(plan, "horizon views", 0.3);
}

TEST(World, OrbitAndObliqueGridSeeNoVoid) {
  Plan plan = HillyPlan(64, 48);
  for (int a = 0; a < 6; ++a) {  // an orbit of radius 50 m at 40 m around the centre
    const double az = a * M_PI / 3;
    AddFrame(&plan, LookAt({50 * std::cos(az), 50 * std::sin(az), 40}, {0, 0, 0}));
  }
  for (int i = 0; i < 3; ++i) {  // an oblique grid: 45 degrees down, looking north
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d eye(-40 + 40 * i, -40 + 40 * j, 25);
      AddFrame(&plan, LookAt(eye, eye + Eigen::Vector3d(0, 1, -1)));
    }
  }
  ExpectNoVoid(plan, "orbit and oblique grid", 0.05);
}

TEST(World, RandomPosesSeeNoVoid) {
  Plan plan = HillyPlan(64, 48);
  for (int k = 0; k < 12; ++k) {
    auto u = [k](int draw) { return Uniform01(5, 16, k, draw); };
    const double x = -60 + 120 * u(0), y = -60 + 120 * u(1);
    const Eigen::Vector3d eye(x, y, 6 + 60 * u(2));
    const double yaw = 2 * M_PI * u(3), pitch = (-80 + 95 * u(4)) * M_PI / 180;
    const Eigen::Vector3d look(
        std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), std::sin(pitch));
    AddFrame(&plan, LookAt(eye, eye + look));
  }
  ExpectNoVoid(plan, "random poses", 0.05);
}

TEST(World, LookingUpSeesSky) {
  Plan plan = HillyPlan(32, 24);
  AddFrame(&plan, LookAt({0, 0, 10}, {0, 100, 200}), 32, 24);
  const Film film = RenderK(plan, 0);
  for (float z : film.flat.at("depth").Get("Z").floats) ASSERT_TRUE(std::isinf(z));
}

TEST(World, SkirtSharesTheTerrainEdgeAndSettlesToThePlane) {
  PlannedTerrain terrain = HillyPlan(8, 8).terrain;
  const TriangleMesh mesh = MakeTerrainMesh(terrain);
  const TriangleMesh skirt = MakeGroundSkirt(terrain, mesh);
  // Every vertex on the terrain's boundary is a skirt vertex, bit for bit.
  size_t boundary = 0, shared = 0;
  for (const Eigen::Vector3f& p : mesh.positions) {
    if (std::abs(p.x()) < 59.999 && std::abs(p.y()) < 59.999) continue;
    ++boundary;
    for (const Eigen::Vector3f& q : skirt.positions) {
      if (p == q) {
        ++shared;
        break;
      }
    }
  }
  EXPECT_GT(boundary, 8u);
  EXPECT_EQ(shared, boundary);
  const double reach = GroundSkirtReach(terrain);
  EXPECT_EQ(GroundHeight(terrain, 60 + GroundFadeWidth(terrain) + 1, 0), kWorldGroundZ);
  double farthest = 0;
  for (const Eigen::Vector3f& q : skirt.positions) {
    farthest = std::max(farthest, static_cast<double>(q.head<2>().cwiseAbs().maxCoeff()));
    if (q.head<2>().cwiseAbs().maxCoeff() > 60 + GroundFadeWidth(terrain)) {
      ASSERT_EQ(q.z(), kWorldGroundZ);
    }
  }
  EXPECT_GE(farthest, reach);
  // A flat terrain's world stays exactly flat: one ring of four quads at z = 0.
  terrain.perlin_amplitude = 0;
  const TriangleMesh flat = MakeGroundSkirt(terrain, MakeTerrainMesh(terrain));
  EXPECT_EQ(flat.triangles.size(), 8u);
  for (const Eigen::Vector3f& q : flat.positions) EXPECT_EQ(q.z(), 0.f);
}

// Smooth surfaces: with the sun at the zenith, no skylight and a uniform
// white material, a pixel's radiance is albedo * sun * n_shading.z: it must
// follow the true surface's normal (from the height function at the pixel's
// world position), not the facet's, and be continuous between neighbours.
TEST(Smooth, TerrainShadingFollowsTheSmoothSurface) {
  Plan plan = HillyPlan(96, 72);
  plan.terrain.perlin_amplitude = 6;
  plan.terrain.perlin_frequency = 0.03;
  plan.terrain.material = "white";
  plan.sun.elevation_deg = 90.0;
  plan.sun.azimuth_deg = 0.0;
  plan.sun.illuminance_lux = 100000.0;
  plan.skylight_intensity = 0;
  AddFrame(&plan, testing::Nadir({0, 0, 40}), 96, 72);
  const Film film = RenderK(plan, 0);
  const auto& r = film.flat.at("rgb").Get("R").floats;
  const auto& x = film.flat.at("worldposition").Get("X").floats;
  const auto& y = film.flat.at("worldposition").Get("Y").floats;
  const auto& nz = film.flat.at("normal").Get("Z").floats;
  // "white" under the sun: radiance albedo * E / pi (times the sun's tint).
  const float albedo_sun = 0.80f * Sky(plan).sun_irradiance().x();
  const double step = TerrainNormalStep(plan.terrain);
  double worst = 0, worst_jump = 0, worst_geometric_jump = 0, worst_geometric = 0;
  const int w = 96, h = 72;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const size_t p = static_cast<size_t>(j) * w + i;
      auto height = [&](double a, double b) { return GroundHeight(plan.terrain, a, b); };
      const double dx = (height(x[p] + step, y[p]) - height(x[p] - step, y[p])) / (2 * step);
      const double dy = (height(x[p], y[p] + step) - height(x[p], y[p] - step)) / (2 * step);
      const double true_nz = 1 / std::sqrt(1 + dx * dx + dy * dy);
      const double shading_nz = r[p] / albedo_sun;
      worst = std::max(worst, std::abs(shading_nz - true_nz));
      worst_geometric = std::max(worst_geometric, std::abs(nz[p] - true_nz));
      if (i + 1 < w) {
        worst_jump = std::max(worst_jump, std::abs(r[p + 1] - r[p]) / double{albedo_sun});
        worst_geometric_jump =
            std::max(worst_geometric_jump, static_cast<double>(std::abs(nz[p + 1] - nz[p])));
      }
    }
  }
  std::printf(
      "n.z vs the true surface: shading worst %.4f, neighbour jump %.4f; "
      "geometric (normal layer) worst %.4f, neighbour jump %.4f\n",
      worst,
      worst_jump,
      worst_geometric,
      worst_geometric_jump);
  EXPECT_LT(worst, 0.025);
  EXPECT_LT(worst_jump, 0.012);
  // The facets are there in the geometry: the smooth shading is what removes them.
  EXPECT_GT(worst_geometric_jump, 4 * worst_jump);
  EXPECT_GT(worst_geometric, 1.5 * worst);
}

TEST(Smooth, CreaseNormalsRoundASphereAndKeepABoxSharp) {
  TriangleMesh sphere = MakeSphereMesh(24, 12);
  const std::vector<Eigen::Vector3f> n = CreaseCornerNormals(sphere);
  ASSERT_EQ(n.size(), 3 * sphere.triangles.size());
  for (size_t t = 0; t < sphere.triangles.size(); ++t) {
    for (int c = 0; c < 3; ++c) {
      // The lathe's surface: radius 0.5 sin(pi t) at z = t - 0.5.
      const Eigen::Vector3f p = sphere.positions[sphere.triangles[t][c]];
      const double rho = std::hypot(p.x(), p.y());
      const double slope = 0.5 * M_PI * std::cos(M_PI * (p.z() + 0.5));  // d radius / dz
      if (rho < 1e-6) continue;  // the poles are cone tips: no normal to compare with
      const Eigen::Vector3f truth =
          Eigen::Vector3d(p.x() / rho, p.y() / rho, -slope).normalized().cast<float>();
      ASSERT_GT(n[3 * t + c].dot(truth), std::cos(4 * M_PI / 180)) << t;
    }
  }
  TriangleMesh box = MakeBoxMesh();
  const std::vector<Eigen::Vector3f> b = CreaseCornerNormals(box);
  for (size_t t = 0; t < box.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = box.triangles[t];
    const Eigen::Vector3f face = (box.positions[tri[1]] - box.positions[tri[0]])
                                     .cross(box.positions[tri[2]] - box.positions[tri[0]])
                                     .normalized();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[3 * t + c].dot(face), 1.f, 1e-6f);
  }
}

// Cloud shadows: the ground under a cumulus deck is darkened where the sun's
// ray crosses a cloud, and the shadow layer says exactly by how much: on a
// uniform flat material the radiance over a sunlit pixel's is the shadow value.
TEST(Clouds, CloudShadowsDarkenTheGroundAsTheShadowLayerSays) {
  Plan plan = testing::FlatPlan(64, 64, 80);
  plan.terrain.size = {2000, 2000};
  plan.terrain.material = "white";
  plan.sky.cloud_type = "cumulus";
  plan.sky.cloud_density = 0.5;
  plan.frames[0].cam_from_world = testing::Nadir({0, 0, 600});
  const Film film = RenderK(plan, 0);
  const auto& r = film.flat.at("rgb").Get("R").floats;
  const auto& g = film.flat.at("rgb").Get("G").floats;
  const auto& b = film.flat.at("rgb").Get("B").floats;
  const auto& shadow = film.flat.at("shadow").Get("Y").floats;
  double sunlit = 0;
  size_t shaded = 0;
  auto lum = [&](size_t p) { return 0.2126 * r[p] + 0.7152 * g[p] + 0.0722 * b[p]; };
  for (size_t p = 0; p < shadow.size(); ++p)
    if (shadow[p] == 1.f) sunlit = lum(p);
  ASSERT_GT(sunlit, 0) << "no pixel in full sun";
  for (size_t p = 0; p < shadow.size(); ++p) {
    if (shadow[p] < 0.95f) ++shaded;
    EXPECT_NEAR(lum(p) / sunlit, shadow[p], 2e-3) << p;  // half-float rgb
  }
  std::printf("cloud shadow: %.1f %% of the ground below 0.95\n", 100.0 * shaded / shadow.size());
  EXPECT_GT(shaded, shadow.size() / 20);
  EXPECT_LT(shaded, shadow.size());
  // A clear sky casts none.
  plan.sky.cloud_type = "none";
  const Film clear = RenderK(plan, 0);
  for (float v : clear.flat.at("shadow").Get("Y").floats) ASSERT_EQ(v, 1.f);
}

// Metals reflect: seen from above with the sun behind, a flat MetalGold ground
// has a gold-tinted highlight many times brighter than its rim, while a
// Lambertian ground is uniformly lit.
TEST(Materials, MetalGoldHasATintedHighlightLambertianDoesNot) {
  auto spread = [](const std::string& material, Eigen::Vector3f* brightest) {
    Plan plan = testing::FlatPlan(64, 48, 90);
    plan.terrain.material = material;
    plan.sun.elevation_deg = 60.0;
    plan.sun.azimuth_deg = 180.0;  // from the south
    plan.sun.illuminance_lux = 100000.0;
    plan.frames[0].cam_from_world = testing::Nadir({0, 0, 10});
    const Film film = RenderK(plan, 0);
    const auto& r = film.flat.at("rgb").Get("R").floats;
    const auto& g = film.flat.at("rgb").Get("G").floats;
    const auto& b = film.flat.at("rgb").Get("B").floats;
    double lo = 1e30, hi = 0;
    for (size_t p = 0; p < r.size(); ++p) {
      const double l = 0.2126 * r[p] + 0.7152 * g[p] + 0.0722 * b[p];
      lo = std::min(lo, l);
      if (l > hi) hi = l, *brightest = Eigen::Vector3f(r[p], g[p], b[p]);
    }
    return hi / lo;
  };
  Eigen::Vector3f gold, white;
  const double metal = spread("MetalGold", &gold), matte = spread("white", &white);
  std::printf("brightest / darkest pixel: MetalGold %.2f, white %.2f\n", metal, matte);
  EXPECT_GT(metal, 3.0);
  EXPECT_NEAR(matte, 1.0, 1e-5);
  EXPECT_GT(gold.x(), gold.y());  // tinted: R > G > B
  EXPECT_GT(gold.y(), gold.z());
}

}  // namespace
}  // namespace lsds::gen

namespace lsds::gen {
namespace {

std::vector<double> LuminanceOf(const Film& film) {
  const auto& r = film.flat.at("rgb").Get("R").floats;
  const auto& g = film.flat.at("rgb").Get("G").floats;
  const auto& b = film.flat.at("rgb").Get("B").floats;
  std::vector<double> y(r.size());
  for (size_t p = 0; p < y.size(); ++p) y[p] = 0.2126 * r[p] + 0.7152 * g[p] + 0.0722 * b[p];
  return y;
}

// The ground-detail measure of issue 45 (docs/generator.md, "Ground detail"):
// the mean |4-neighbour Laplacian| of the linear luminance over the mean
// luminance, on the pixels whose four neighbours are terrain too.
double LaplacianMeasure(const Film& film, int w, int h, uint32_t terrain_class) {
  const std::vector<double> y = LuminanceOf(film);
  const auto& cls = film.flat.at("classid").Get("id").uints;
  double laplacian = 0, luminance = 0;
  size_t n = 0;
  for (int j = 1; j + 1 < h; ++j) {
    for (int i = 1; i + 1 < w; ++i) {
      const size_t p = static_cast<size_t>(j) * w + i;
      if (cls[p] != terrain_class || cls[p - 1] != terrain_class || cls[p + 1] != terrain_class ||
          cls[p - w] != terrain_class || cls[p + w] != terrain_class)
        continue;
      laplacian += std::abs(4 * y[p] - y[p - 1] - y[p + 1] - y[p - w] - y[p + w]);
      luminance += y[p];
      ++n;
    }
  }
  return n > 0 && luminance > 0 ? laplacian / luminance : 0;
}

// Grass seen from 2.5 m at 3 cm per pixel shows blades and clumps: the
// Laplacian measure reaches a photo's (>= 0.05; 0.014 before the detail), and
// the detail sits in the world: a frame moved by 10 pixels sees the same
// ground 10 pixels over.
TEST(GroundDetail, GrassAtThreeCentimetresPerPixelHasDetailAnchoredInTheWorld) {
  constexpr int kSize = 96;
  constexpr double kGsd = 0.03;
  Plan plan = testing::FlatPlan(kSize, kSize, 60);
  plan.terrain.material = "grassy";
  plan.sun.illuminance_lux = 100000;
  const double fx = plan.frames[0].camera.fx;
  plan.frames[0].cam_from_world = testing::Nadir({0.3, 0.2, kGsd * fx});
  plan.frames.push_back(plan.frames[0]);
  plan.frames[1].index = 1;
  plan.frames[1].cam_from_world = testing::Nadir({0.3 + 10 * kGsd, 0.2, kGsd * fx});
  const Film film = RenderK(plan, 0, 4);
  const double measure = LaplacianMeasure(film, kSize, kSize, 1);
  std::printf(
      "grass at %.0f cm per pixel: mean |Laplacian| / mean luminance %.4f\n", 100 * kGsd, measure);
  EXPECT_GE(measure, 0.05);
  EXPECT_LT(measure, 1.0);  // detail, not noise
  const Film moved = RenderK(plan, 1, 4);
  const std::vector<double> a = LuminanceOf(film), b = LuminanceOf(moved);
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  size_t n = 0;
  for (int j = 0; j < kSize; ++j) {
    for (int i = 0; i + 10 < kSize; ++i) {
      const double u = a[static_cast<size_t>(j) * kSize + i + 10];
      const double v = b[static_cast<size_t>(j) * kSize + i];
      sa += u, sb += v, saa += u * u, sbb += v * v, sab += u * v, ++n;
    }
  }
  const double cov = sab / n - sa / n * sb / n;
  const double correlation =
      cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
  std::printf("the same ground from a frame 10 pixels over: correlation %.3f\n", correlation);
  EXPECT_GT(correlation, 0.8);
}

// Shadows keep the sky's light: on flat open ground the shadow of a box is
// lit by the whole sky but the part the box hides, so shadow / sun is close to
// the analytic ratio ambient / (ambient + sun x sin(elevation)), and under it,
// never black.
TEST(SkyLight, ShadowsOnOpenGroundKeepTheSkysLight) {
  Plan plan = testing::FlatPlan(96, 96, 60);
  plan.terrain.material = "white";
  plan.sun.illuminance_lux = 100000;
  plan.sun.elevation_deg = 45;
  plan.objects.push_back(testing::Box("box", 7, {0, 0, 2}, {4, 4, 4}));
  plan.frames[0].cam_from_world = testing::Nadir({0, 0, 30});
  const Film film = RenderK(plan, 0, 4);
  const std::vector<double> y = LuminanceOf(film);
  const auto& shadow = film.flat.at("shadow").Get("Y").floats;
  const auto& cls = film.flat.at("classid").Get("id").uints;
  double in_shadow = 0, in_sun = 0;
  size_t shadowed = 0, sunlit = 0;
  // Pixels whose 3x3 neighbourhood is all ground in shadow, or all in the sun:
  // no sample of theirs crosses the shadow's edge.
  const int w = 96, h = 96;
  auto all = [&](int i, int j, auto&& test) {
    for (int b = j - 1; b <= j + 1; ++b)
      for (int a = i - 1; a <= i + 1; ++a)
        if (!test(static_cast<size_t>(b) * w + a)) return false;
    return true;
  };
  for (int j = 1; j + 1 < h; ++j) {
    for (int i = 1; i + 1 < w; ++i) {
      const size_t p = static_cast<size_t>(j) * w + i;
      if (all(i, j, [&](size_t q) { return cls[q] == 1 && shadow[q] < 0.5f; }))
        in_shadow += y[p], ++shadowed;
      if (all(i, j, [&](size_t q) { return cls[q] == 1 && shadow[q] == 1.f; }))
        in_sun += y[p], ++sunlit;
    }
  }
  ASSERT_GT(shadowed, 30u);
  ASSERT_GT(sunlit, 30u);
  const Sky sky(plan);
  auto lum = [](const Eigen::Vector3f& c) {
    return 0.2126 * c.x() + 0.7152 * c.y() + 0.0722 * c.z();
  };
  const double sun = lum(sky.sun_irradiance()) * std::sin(M_PI / 4);
  const double analytic = lum(sky.ambient()) / (lum(sky.ambient()) + sun);
  const double measured = (in_shadow / shadowed) / (in_sun / sunlit);
  std::printf("shadow / sun on open ground: measured %.4f, analytic sky / (sun + sky) %.4f\n",
              measured,
              analytic);
  EXPECT_GT(measured, 0.7 * analytic);
  EXPECT_LE(measured, 1.02 * analytic);
}

// The sky has no seam at the horizon: just above and just below it the same
// haze, and fogged distant ground fades to the sky just above it.
TEST(Sky, TheHorizonIsHazeWithoutASeam) {
  Plan plan = testing::FlatPlan();
  plan.sun.elevation_deg = 30;
  for (const double fog : {0.0, 0.002}) {
    plan.fog_density = fog;
    const Sky sky(plan);
    for (int a = 0; a < 8; ++a) {
      const double az = a * M_PI / 4;
      const Eigen::Vector3d level(std::cos(az), std::sin(az), 0);
      const Eigen::Vector3f above =
          sky.Radiance((level + Eigen::Vector3d(0, 0, 1e-3)).normalized());
      const Eigen::Vector3f below =
          sky.Radiance((level - Eigen::Vector3d(0, 0, 1e-3)).normalized());
      EXPECT_LT((above - below).norm(), 0.01 * above.norm()) << az;
      EXPECT_LT((sky.Haze(level) - above).norm(), 0.01 * above.norm()) << az;
    }
    // Brighter towards the sun (east, +x) than away from it (Perez / Preetham).
    auto lum = [](const Eigen::Vector3f& c) {
      return 0.2126 * c.x() + 0.7152 * c.y() + 0.0722 * c.z();
    };
    EXPECT_GT(lum(sky.Haze(Eigen::Vector3d(1, 0, 0))),
              1.5 * lum(sky.Haze(Eigen::Vector3d(-1, 0, 0))));
    // Ground 20 km away is haze: nearly the sky's horizon.
    EXPECT_LT(sky.HazeTransmittance(20000), 0.35) << fog;
    EXPECT_EQ(sky.HazeTransmittance(500), std::exp(-fog * 500)) << fog;
  }
}

}  // namespace
}  // namespace lsds::gen
