// Post-process materials (docs/generator.md "Post-process materials"): each
// effect changes the RGB as documented, is deterministic, and leaves every
// truth layer byte for byte as it was, end to end through GenerateCollection.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

#include <gtest/gtest.h>

#include "generator/generate.h"
#include "generator/render/integrator.h"
#include "generator/render/post_process.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/json_io.h"
#include "libs/util/atomic_file.h"
#include "tests/generator/test_plans.h"
#include "tests/test_util.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;

Plan TwoFramePlan() {
  Plan plan = testing::FlatPlan(48, 36);
  plan.objects.push_back(testing::Box("B1", 1, {0, 0, 1}, {3, 3, 2}));
  const PlannedFrame first = plan.frames[0];
  plan.frames.clear();
  for (int f = 0; f < 2; ++f) {
    PlannedFrame frame = first;
    frame.index = f;
    frame.time = 0.5 * f;
    frame.cam_from_world = testing::Nadir({1.5 * f - 1, 0, 15});
    plan.frames.push_back(frame);
  }
  return plan;
}

Film Render(const Plan& plan, size_t k) {
  static EmbreeDevice device;
  const SceneAssets assets = BuildSceneAssets(plan);
  const WorldState world = WorldAt(plan, plan.frames[k]);
  const RenderScene scene(device, plan, assets, world);
  RenderSettings settings;
  settings.sampler = {4, 1.0, plan.seed};
  PreviousView previous;
  std::optional<WorldState> previous_world;
  std::optional<RenderScene> previous_scene;
  if (k > 0) {
    previous.frame = &plan.frames[k - 1];
    previous_world = WorldAt(plan, plan.frames[k - 1]);
    previous.world = &*previous_world;
    previous_scene.emplace(device, plan, assets, *previous_world);
    previous.scene = &*previous_scene;
  }
  return RenderFrame(scene, Sky(plan), plan.frames[k], previous, settings);
}

const std::vector<float>& R(const Film& film) { return film.flat.at("rgb").Get("R").floats; }

void ExpectTruthUnchanged(const Film& a, const Film& b) {
  for (const auto& [semantic, image] : a.flat) {
    if (semantic == "rgb") continue;
    for (const exr::FlatChannel& c : image.channels()) {
      const exr::FlatChannel& d = b.flat.at(semantic).Get(c.name);
      EXPECT_EQ(c.uints, d.uints) << semantic;
      // Bit-equal floats (NaN == NaN); a uint channel has no floats, and
      // memcmp must not see its null data pointer.
      ASSERT_EQ(c.floats.size(), d.floats.size()) << semantic;
      if (!c.floats.empty()) {
        EXPECT_EQ(0, std::memcmp(c.floats.data(), d.floats.data(), c.floats.size() * 4))
            << semantic;
      }
    }
  }
}

TEST(PostProcess, EachEffectChangesRgbOnlyAndIsDeterministic) {
  const Plan plan = TwoFramePlan();
  const Film plain = Render(plan, 1);
  for (const std::string& name : PostProcessNames()) {
    Film a = Render(plan, 1), b = Render(plan, 1);
    ApplyPostProcess({name}, plan.seed, plan.frames[1], plan.exposure, &a);
    ApplyPostProcess({name}, plan.seed, plan.frames[1], plan.exposure, &b);
    ExpectTruthUnchanged(plain, a);
    EXPECT_EQ(R(a), R(b)) << name;  // deterministic
    EXPECT_NE(R(a), R(plain)) << name;
  }
}

TEST(PostProcess, EdgeBlurTouchesOnlySilhouettes) {
  const Plan plan = TwoFramePlan();
  const Film plain = Render(plan, 0);
  Film blurred = Render(plan, 0);
  ApplyPostProcess({"edge_blur"}, plan.seed, plan.frames[0], plan.exposure, &blurred);
  const auto& id = plain.flat.at("instanceid").Get("id").uints;
  const int w = 48, h = 36;
  size_t changed = 0;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const size_t p = static_cast<size_t>(y) * w + x;
      if (R(plain)[p] == R(blurred)[p]) continue;
      ++changed;
      bool near_edge = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) near_edge |= id[(y + dy) * w + (x + dx)] != id[p];
      EXPECT_TRUE(near_edge) << x << "," << y;
    }
  EXPECT_GT(changed, 20u);
}

TEST(PostProcess, VignettingIsCosineToTheFourth) {
  const Plan plan = TwoFramePlan();
  const Film plain = Render(plan, 0);
  Film v = Render(plan, 0);
  ApplyPostProcess({"Vignetting"}, plan.seed, plan.frames[0], plan.exposure, &v);
  const PinholeCamera& cam = plan.frames[0].camera;
  const double c = 1 / cam.RayThroughPixelCenter(0, 0).norm();
  EXPECT_NEAR(R(v)[0] / R(plain)[0], std::pow(c, 4), 1e-5);
}

TEST(PostProcess, MotionBlurOnlyWhereThereIsMotion) {
  const Plan plan = TwoFramePlan();
  Film first = Render(plan, 0), first_plain = Render(plan, 0);
  ApplyPostProcess({"MotionBlur"}, plan.seed, plan.frames[0], plan.exposure, &first);
  EXPECT_EQ(R(first), R(first_plain));  // frame 0 has no valid motion
}

TEST(PostProcess, UnknownNamesAreReportedWithASuggestion) {
  EXPECT_EQ(CanonicalPostProcess("cartoon_style"), "CartoonStyle");
  EXPECT_EQ(CanonicalPostProcess("Defocus"), "EdgeBlur");
  const std::vector<std::string> unknown = UnknownPostProcess({"EdgeBlur", "CartoonStlye"});
  ASSERT_EQ(unknown.size(), 1u);
  EXPECT_NE(unknown[0].find("did you mean 'CartoonStyle'"), std::string::npos) << unknown[0];
}

// A 200 x 100 checkerboard film whose left half lies at `left_m` and right half at `right_m`.
Film TwoDepthFilm(float left_m, float right_m) {
  Film film;
  exr::FlatImage rgb(200, 100), depth(200, 100);
  for (const char* c : {"R", "G", "B"}) rgb.AddChannel(c, exr::PixelType::kFloat);
  depth.AddChannel("Z", exr::PixelType::kFloat);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 200; ++x) {
      const float v = ((x / 2 + y / 2) % 2) ? 1.f : 0.f;
      for (const char* c : {"R", "G", "B"}) rgb.F(c, x, y) = v;
      depth.F("Z", x, y) = x < 100 ? left_m : right_m;
    }
  film.flat.emplace("rgb", std::move(rgb));
  film.flat.emplace("depth", std::move(depth));
  return film;
}

// The variance of R over the columns [x0, x1), rows away from the borders.
double Variance(const Film& film, int x0, int x1) {
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int y = 20; y < 80; ++y)
    for (int x = x0; x < x1; ++x) {
      const double v = film.flat.at("rgb").Get("R").floats[static_cast<size_t>(y) * 200 + x];
      sum += v, sum2 += v * v, ++n;
    }
  return sum2 / n - (sum / n) * (sum / n);
}

TEST(PostProcess, DepthOfFieldKeepsTheFocusSharpAndBlursByTheThinLens) {
  PlannedFrame frame;
  frame.camera.width = 200;
  frame.camera.height = 100;
  frame.camera.fx = 200;  // a 36 mm sensor: f = 36 mm (200 px of 0.18 mm)
  PlannedExposure lens;
  lens.focus_distance_m = 2;
  lens.f_number = 1.4;
  Film film = TwoDepthFilm(2, 20);
  Film sharp = film;
  const std::optional<double> focused = ApplyPostProcess({"DepthOfField"}, 1, frame, lens, &film);
  ASSERT_TRUE(focused.has_value());
  EXPECT_EQ(*focused, 2);
  // In focus: the pixels are the rendered ones, bit for bit (away from the depth edge).
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 80; ++x)
      EXPECT_EQ(film.flat.at("rgb").F("R", x, y), sharp.flat.at("rgb").F("R", x, y));
  // At 20 m: c = f^2 / (N (s - f)) |z - s| / z = 0.036^2 / (1.4 x 1.964) x 0.9 = 0.424 mm, 2.4 px
  // of 0.18 mm: the 2 px checkerboard is mostly averaged away.
  EXPECT_LT(Variance(film, 120, 200), 0.5 * Variance(sharp, 120, 200));
  // Without a focus distance it focuses at the centre pixel (x 100: the far half).
  lens.focus_distance_m.reset();
  Film autofocus = TwoDepthFilm(2, 20);
  EXPECT_EQ(*ApplyPostProcess({"dof"}, 1, frame, lens, &autofocus), 20);
  EXPECT_LT(Variance(autofocus, 0, 80), 0.5 * Variance(sharp, 0, 80));
  EXPECT_GT(Variance(autofocus, 120, 200), 0.99 * Variance(sharp, 120, 200));
}

TEST(PostProcess, GeneratedTruthIsByteEqualWithAndWithoutEffects) {
  const lsds::testing::TempDir dir;
  const fs::path a = dir / "plain";
  const fs::path b = dir / "effects";
  GenerateOptions options;
  options.progress = false;
  options.threads = 2;
  options.output = a;
  Plan plan = TwoFramePlan();
  GenerateCollection(plan, options);
  plan.post_process = PostProcessNames();
  options.output = b;
  GenerateCollection(plan, options);
  size_t compared = 0;
  CollectionReader(a).ForEachFrame([&](const Frame& f) {
    for (const auto& [layer, file] : f.files) {
      if (layer == "rgb") {
        EXPECT_NE(ReadFile(a / file), ReadFile(b / file)) << file;
      } else {
        EXPECT_EQ(ReadFile(a / file), ReadFile(b / file)) << file;
        ++compared;
      }
    }
  });
  EXPECT_GE(compared, 16u);
}

}  // namespace
}  // namespace lsds::gen
