// Post-process materials (docs/generator.md "Post-process materials"): each
// effect changes the RGB as documented, is deterministic, and leaves every
// truth layer byte for byte as it was, end to end through GenerateCollection.
#include <cmath>
#include <cstring>
#include <filesystem>

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
    ApplyPostProcess({name}, plan.seed, plan.frames[1], &a);
    ApplyPostProcess({name}, plan.seed, plan.frames[1], &b);
    ExpectTruthUnchanged(plain, a);
    EXPECT_EQ(R(a), R(b)) << name;  // deterministic
    EXPECT_NE(R(a), R(plain)) << name;
  }
}

TEST(PostProcess, EdgeBlurTouchesOnlySilhouettes) {
  const Plan plan = TwoFramePlan();
  const Film plain = Render(plan, 0);
  Film blurred = Render(plan, 0);
  ApplyPostProcess({"edge_blur"}, plan.seed, plan.frames[0], &blurred);
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
  ApplyPostProcess({"Vignetting"}, plan.seed, plan.frames[0], &v);
  const PinholeCamera& cam = plan.frames[0].camera;
  const double c = 1 / cam.RayThroughPixelCenter(0, 0).norm();
  EXPECT_NEAR(R(v)[0] / R(plain)[0], std::pow(c, 4), 1e-5);
}

TEST(PostProcess, MotionBlurOnlyWhereThereIsMotion) {
  const Plan plan = TwoFramePlan();
  Film first = Render(plan, 0), first_plain = Render(plan, 0);
  ApplyPostProcess({"MotionBlur"}, plan.seed, plan.frames[0], &first);
  EXPECT_EQ(R(first), R(first_plain));  // frame 0 has no valid motion
}

TEST(PostProcess, UnknownNamesAreReportedWithASuggestion) {
  EXPECT_EQ(CanonicalPostProcess("cartoon_style"), "CartoonStyle");
  EXPECT_EQ(CanonicalPostProcess("Defocus"), "EdgeBlur");
  const std::vector<std::string> unknown = UnknownPostProcess({"EdgeBlur", "CartoonStlye"});
  ASSERT_EQ(unknown.size(), 1u);
  EXPECT_NE(unknown[0].find("did you mean 'CartoonStyle'"), std::string::npos) << unknown[0];
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
