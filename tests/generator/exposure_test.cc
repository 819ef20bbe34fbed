// Physical light and camera (docs/generator.md, "Physical light and camera"):
// the sun in lux and the sky in cd/m^2, the camera's exposure (auto by
// default, or ISO / shutter / f-number / EV100) and the tone curve of the
// 8-bit exports, end to end: LSCENE/LCAP -> generate -> the rgb EXR and the
// frame's exposure record -> the 8-bit image `lsds convert` writes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "generator/generate.h"
#include "generator/lang/planner.h"
#include "generator/plan/plan_json.h"
#include "generator/plan_source.h"
#include "generator/render/exposure.h"
#include "generator/render/sky.h"
#include "generator/scene/materials.h"
#include "libs/exr/flat_image.h"
#include "libs/imaging/srgb_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "tests/lang/plan_text.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;

using testing::PlanText;

// A noon sun (elevation 85 degrees) of 100000 lux over sand, a clear sky of
// 7000 cd/m^2; a nadir view and an oblique one that sees the horizon and sky.
std::string NoonScene(const std::string& light = "intensity:100000") {
  return "LSCENE = ONE(S) ONE(DL) ONE(SL) ONE(W)\n"
         "S = skybox{color:blue}\n"
         "DL = light{elevation:85,azimuth:180," +
         light +
         "}\n"
         "SL = skylight{intensity:0.3}\n"
         "W = terrain{size:[300,300],height:{Perlin:3},frequency:0.03,material:sandy}\n";
}

std::string Capture(const std::string& csettings) {
  return "LCAP = ONE(CO) ONE(P)\n"
         "CO = camera{csettings:{fov:70,res:[96,72]" +
         csettings +
         "}}\n"
         "P = path{waypoints:[[0,0,40],{position:[0,0,30],look_at:[0,300,20]}]}\n";
}

struct Rendered {
  nlohmann::json collection;
  std::vector<exr::FlatImage> rgb;
};

Rendered Generate(const fs::path& out, const Plan& plan) {
  gen::GenerateOptions options;
  options.output = out;
  options.spp = 1;
  options.progress = false;
  gen::GenerateCollection(plan, options);
  Rendered r;
  r.collection = nlohmann::json::parse(ReadFile(out / "collection.json"));
  for (const auto& frame : r.collection["frames"])
    r.rgb.push_back(
        exr::ReadFlatExr(out / frame["files"]["rgb"].get<std::string>(), {"R", "G", "B"}));
  return r;
}

// Share of pixels with a channel at 255 in the 8-bit export.
double ClippedShare(const exr::FlatImage& rgb, imaging::ToneMap tonemap, double ev = 0) {
  imaging::DisplayOptions display;
  display.tonemap = tonemap;
  display.exposure_ev = ev;
  const cv::Mat bgr = imaging::ToSrgb8(rgb, display);
  size_t clipped = 0;
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      if (p[0] == 255 || p[1] == 255 || p[2] == 255) ++clipped;
    }
  return static_cast<double>(clipped) / (bgr.rows * bgr.cols);
}

double MeanLuminance(const exr::FlatImage& rgb) {
  const auto &r = rgb.Get("R").floats, &g = rgb.Get("G").floats, &b = rgb.Get("B").floats;
  double sum = 0;
  for (size_t i = 0; i < r.size(); ++i) sum += 0.2126 * r[i] + 0.7152 * g[i] + 0.0722 * b[i];
  return sum / r.size();
}

TEST(Exposure, NoonSunOf100000LuxWithAutoExposureClipsUnderOnePercent) {
  testing::TempDir dir;
  const Plan plan = PlanText(NoonScene(), Capture(""));
  EXPECT_DOUBLE_EQ(plan.sun.illuminance_lux, 100000);
  EXPECT_FALSE(plan.exposure.Manual());
  const Rendered r = Generate(dir / "out", plan);
  ASSERT_EQ(r.rgb.size(), 2u);
  for (size_t k = 0; k < r.rgb.size(); ++k) {
    const nlohmann::json& e = r.collection["frames"][k]["exposure"];
    ASSERT_EQ(e["mode"], "auto");
    const double ev100 = e["ev100"], scale = e["scale"], metered = e["metered_cd_m2"];
    // The meter's calibration (K = 12.5) and the saturation-based scale.
    EXPECT_NEAR(ev100, std::log2(metered * 100 / 12.5), 1e-9);
    EXPECT_NEAR(scale, 1 / (1.2 * std::exp2(ev100)), 1e-12 * scale);
    // Sunlit sand of albedo ~0.35 at 100000 lux: about 10^4 cd/m^2, EV100 ~ 16.
    EXPECT_GT(ev100, 14.5);
    EXPECT_LT(ev100, 17.5);
    const double filmic = ClippedShare(r.rgb[k], imaging::ToneMap::kFilmic);
    const double clamp = ClippedShare(r.rgb[k], imaging::ToneMap::kClamp);
    // Without an exposure (the rgb as absolute cd/m^2, what a unitless
    // renderer with intensity 100000 showed): every pixel is white.
    const double unexposed = ClippedShare(r.rgb[k], imaging::ToneMap::kClamp, -std::log2(scale));
    std::printf(
        "frame %zu: EV100 %.2f, clipped: filmic %.2f %%, clamp %.2f %%, unexposed %.1f %%\n",
        k,
        ev100,
        100 * filmic,
        100 * clamp,
        100 * unexposed);
    EXPECT_LT(filmic, 0.01);
    EXPECT_LT(clamp, 0.01);
    EXPECT_EQ(unexposed, 1.0);
    // The mean sits in the mid tones, not near black or white.
    const double mean = MeanLuminance(r.rgb[k]);
    EXPECT_GT(mean, 0.05);
    EXPECT_LT(mean, 0.3);
  }
}

TEST(Exposure, SunnySixteenManualExposureGivesASensibleImage) {
  testing::TempDir dir;
  const Plan plan = PlanText(NoonScene(), Capture(",ev100:15"));
  ASSERT_TRUE(plan.exposure.Manual());
  const Rendered r = Generate(dir / "out", plan);
  const nlohmann::json& e = r.collection["frames"][0]["exposure"];
  EXPECT_EQ(e["mode"], "manual");
  EXPECT_EQ(e["ev100"], 15.0);
  EXPECT_FALSE(e.contains("metered_cd_m2"));
  // Sunlit sand (albedo ~0.35, 100000 lux: ~10^4 cd/m^2) over the saturation
  // luminance 1.2 * 2^15: about 0.28.
  const double mean = MeanLuminance(r.rgb[0]);
  std::printf("sunny 16 (EV100 15): mean exposed luminance %.3f, clipped %.2f %%\n",
              mean,
              100 * ClippedShare(r.rgb[0], imaging::ToneMap::kFilmic));
  EXPECT_GT(mean, 0.15);
  EXPECT_LT(mean, 0.45);
  EXPECT_LT(ClippedShare(r.rgb[0], imaging::ToneMap::kFilmic), 0.01);
  // Sand is not white: the 8-bit sand is a mid tone.
  imaging::DisplayOptions display;
  const cv::Mat bgr = imaging::ToSrgb8(r.rgb[0], display);
  EXPECT_LT(cv::mean(bgr)[1], 200);
  EXPECT_GT(cv::mean(bgr)[1], 60);
}

// Doubling the shutter time doubles the exposure: every linear pixel value
// doubles (exactly: a power of two in half floats), EV100 drops by 1, and the
// truth layers stay byte for byte the same.
TEST(Exposure, DoublingTheShutterDoublesLinearPixelValuesAndKeepsTheTruth) {
  testing::TempDir dir;
  const Rendered fast =
      Generate(dir / "fast", PlanText(NoonScene(), Capture(",shutter:0.002,f_number:8,iso:100")));
  const Rendered slow =
      Generate(dir / "slow", PlanText(NoonScene(), Capture(",shutter:0.004,fnumber:8,iso:100")));
  const double ev_fast = fast.collection["frames"][0]["exposure"]["ev100"];
  const double ev_slow = slow.collection["frames"][0]["exposure"]["ev100"];
  EXPECT_NEAR(ev_fast, std::log2(64 / 0.002), 1e-9);
  EXPECT_NEAR(ev_fast - ev_slow, 1.0, 1e-9);
  for (size_t k = 0; k < fast.rgb.size(); ++k) {
    size_t compared = 0;
    for (const char* c : {"R", "G", "B"}) {
      const auto& a = fast.rgb[k].Get(c).floats;
      const auto& b = slow.rgb[k].Get(c).floats;
      for (size_t i = 0; i < a.size(); ++i) {
        if (!(b[i] < 60000.f) || !(a[i] > 1e-4f)) continue;  // half overflow or subnormal
        ASSERT_EQ(b[i], 2 * a[i]) << c << " pixel " << i;
        ++compared;
      }
    }
    EXPECT_GT(compared, fast.rgb[k].Get("R").floats.size() * 2);
    // Every truth file is the same bytes.
    for (const auto& [layer, file] : fast.collection["frames"][k]["files"].items()) {
      if (layer == "rgb") continue;
      EXPECT_EQ(ReadFile(dir / "fast" / file.get<std::string>()),
                ReadFile(dir / "slow" / file.get<std::string>()))
          << layer;
    }
  }
  // ISO 200 at the fast shutter is the slow shutter's exposure.
  const Plan iso = PlanText(NoonScene(), Capture(",shutter:0.002,f_number:8,iso:200"));
  EXPECT_NEAR(
      gen::Ev100FromSettings(*iso.exposure.f_number, *iso.exposure.shutter_s, *iso.exposure.iso),
      ev_slow,
      1e-9);
}

// UC1a's templates (docs/generator.md, "Templates with a white background"):
// under auto exposure a white ground is metered to a mid grey; the template
// recipe, exposure_compensation 3.3 (log2 of the meter's 9.6 from the mean to
// saturation, rounded up) with the clamp tone curve, keeps it white.
TEST(Exposure, TemplateRecipeKeepsAWhiteBackgroundWhite) {
  const std::string white =
      "LSCENE = ONE(S) ONE(DL) ONE(SL) ONE(W)\n"
      "S = skybox{color:blue}\n"
      "DL = light{elevation:60,azimuth:180,intensity:100000}\n"
      "SL = skylight{intensity:0.3}\n"
      "W = terrain{size:[300,300],material:white}\n";
  const std::string nadir =
      "LCAP = ONE(CO) ONE(P)\n"
      "CO = camera{csettings:{fov:60,res:[48,36]";
  const std::string path = "}}\nP = path{waypoints:[[0,0,30],[5,0,30]]}\n";
  auto median_green = [](const exr::FlatImage& rgb) {
    imaging::DisplayOptions display;
    display.tonemap = imaging::ToneMap::kClamp;
    const cv::Mat bgr = imaging::ToSrgb8(rgb, display);
    std::vector<int> g;
    for (int y = 0; y < bgr.rows; ++y)
      for (int x = 0; x < bgr.cols; ++x) g.push_back(bgr.at<cv::Vec3b>(y, x)[1]);
    std::nth_element(g.begin(), g.begin() + g.size() / 2, g.end());
    return g[g.size() / 2];
  };
  testing::TempDir dir;
  const Rendered metered = Generate(dir / "auto", PlanText(white, nadir + path));
  const Rendered templ =
      Generate(dir / "template", PlanText(white, nadir + ",exposure_compensation:3.3" + path));
  const int grey = median_green(metered.rgb[0]), kept = median_green(templ.rgb[0]);
  std::printf("white ground in 8 bits: auto exposure %d, template recipe %d\n", grey, kept);
  EXPECT_LT(grey, 128);
  EXPECT_EQ(kept, 255);
}

TEST(Exposure, CompensationScalesByPowersOfTwo) {
  PlannedExposure p;
  p.ev100 = 12;
  p.compensation_ev = 1;
  gen::Film film = gen::Film::Make(2, 2, 1, false);
  const gen::FrameExposure e = gen::MeterExposure(p, film);
  EXPECT_DOUBLE_EQ(e.scale, 2 / (1.2 * 4096));
  // The shutter the EV100 means at f/8, ISO 100: 64 / 2^12 s.
  EXPECT_DOUBLE_EQ(e.shutter_s, 64.0 / 4096);
}

TEST(LightUnits, SunAndSkyAreInLuxAndLegacyPlansKeepTheirLook) {
  // The paper's lux, and the explicit key; a dusk sun of 50 lux is 50 lux.
  EXPECT_DOUBLE_EQ(PlanText(NoonScene("intensity:50000"), Capture("")).sun.illuminance_lux, 50000);
  EXPECT_DOUBLE_EQ(PlanText(NoonScene("illuminance:20"), Capture("")).sun.illuminance_lux, 20);
  const Plan dusk = PlanText(NoonScene("intensity:50"), Capture(""));
  EXPECT_DOUBLE_EQ(dusk.sun.illuminance_lux, 50);
  // 50 lux at 85 degrees up is no daylight: kept, with a located warning naming the old scale.
  ASSERT_EQ(dusk.warnings.size(), 1u);
  EXPECT_NE(dusk.warnings[0].find("s.lscene:3:"), std::string::npos) << dusk.warnings[0];
  EXPECT_NE(dusk.warnings[0].find("a sun of 50 lux high in the sky is darker than dusk"),
            std::string::npos)
      << dusk.warnings[0];
  EXPECT_TRUE(PlanText(NoonScene(), Capture("")).warnings.empty());
  EXPECT_EQ(PlanText(NoonScene("intensity:400000"), Capture("")).warnings.size(), 1u);
  // A sky change in the capture is judged too.
  const Plan bright_sky =
      PlanText(NoonScene(),
               "LCAP = ONE(CO) ONE(P) ONE(A)\nCO = camera{csettings:{res:[96,72]}}\n"
               "P = path{create point:{position:[0,0,50],count:1}}\n"
               "A = collection{S:{frame:0,intensity:500000}}\n");
  ASSERT_EQ(bright_sky.warnings.size(), 1u);
  EXPECT_NE(bright_sky.warnings[0].find("c.lcap:4:"), std::string::npos) << bright_sky.warnings[0];
  // The sky's intensity is the lux it gives the ground: what the renderer's skylight term gives a
  // horizontal surface at skylight 1 (pi x the ambient radiance's luminance).
  const Plan sky = PlanText(
      "LSCENE = ONE(S) ONE(W)\nS = skybox{color:[0.5,0.5,0.5],intensity:20000}\n"
      "W = terrain{size:[10,10]}\n",
      Capture(""));
  // Grey 0.5 at the zenith, 0.25 + 0.45 = 0.7 at the horizon: 20000 / (pi (0.6 + 0.4 x 1.4)).
  EXPECT_NEAR(sky.sky.luminance_cd_m2, 20000 / (M_PI * 1.16), 1e-9);
  PlannedEnvironment unit_skylight = EnvironmentOf(sky);
  unit_skylight.skylight_intensity = 1;
  const gen::Sky rendered(sky, unit_skylight);
  EXPECT_NEAR(M_PI * RelativeLuminance(rendered.ambient().cast<double>()), 20000, 20000 * 1e-6);
  const Plan nits =
      PlanText("LSCENE = ONE(S) ONE(W)\nS = skybox{luminance:4000}\nW = terrain{size:[10,10]}\n",
               Capture(""));
  EXPECT_DOUBLE_EQ(nits.sky.luminance_cd_m2, 4000);
  EXPECT_NE(testing::PlanErrorOf("LSCENE = ONE(S)\nS = skybox{color:[0,0,0],intensity:5000}\n")
                .find("s.lscene:2:"),
            std::string::npos);
  // Plans written before the units read as they were meant.
  nlohmann::json old = PlanToJson(nits);
  old["sun"].erase("illuminance_lux");
  old["sun"]["intensity"] = 3;
  old["sky"].erase("luminance_cd_m2");
  old["sky"]["intensity"] = 1;
  old.erase("exposure");
  const Plan read = PlanFromJson(old, "old-plan.json");
  EXPECT_NEAR(read.sun.illuminance_lux, 3 * M_PI * 1e4, 1e-6);
  EXPECT_NEAR(read.sky.luminance_cd_m2, RelativeLuminance(read.sky.color) * 1e4, 1e-6);
  EXPECT_FALSE(read.exposure.Manual());
  // The exposure round-trips.
  const Plan manual = PlanText(NoonScene(), Capture(",ev100:13.5,exposure_compensation:-0.5"));
  const Plan again = PlanFromJson(PlanToJson(manual), "plan.json");
  EXPECT_TRUE(again.exposure == manual.exposure);
  EXPECT_EQ(*again.exposure.ev100, 13.5);
}

TEST(LightUnits, BadExposureSettingsAreLocatedErrors) {
  auto message = [](const std::string& csettings) {
    try {
      PlanText(NoonScene(), Capture(csettings));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(",shutter:0.01").find("f_number"), std::string::npos)
      << message(",shutter:0.01");
  EXPECT_NE(message(",ev100:15,iso:200").find("not both"), std::string::npos);
  EXPECT_NE(message(",iso:-5").find("iso must be > 0"), std::string::npos);
  EXPECT_NE(message(",shutter:0.01").find("c.lcap:"), std::string::npos)
      << message(",shutter:0.01");
  EXPECT_NE(message(",exposure_compensation:40").find("within [-10, 10]"), std::string::npos);
}

// The built-in material families vary in space at two scales (patches and
// detail), dry sand has a measured-like albedo, metals are metallic.
TEST(Materials, FamiliesVaryInSpaceAndSandIsNotWhite) {
  const gen::Perlin noise(11);
  for (const char* name :
       {"grassy", "sandy", "rocky", "soil", "asphalt", "metal", "painted_red", "concrete"}) {
    const gen::Material& m = gen::FindMaterial(name, "test");
    auto lum = [](const Eigen::Vector3f& c) {
      return 0.2126 * c.x() + 0.7152 * c.y() + 0.0722 * c.z();
    };
    // Coefficient of variation over a 1 m patch (detail) and over 400 m
    // (patches), sampled on grids.
    auto cv = [&](double spacing) {
      double sum = 0, sum2 = 0;
      int n = 0;
      for (int i = 0; i < 40; ++i)
        for (int j = 0; j < 40; ++j) {
          const double l = lum(
              gen::Albedo(m, noise, Eigen::Vector3f(i * spacing + 0.37, j * spacing + 0.11, 0.3)));
          sum += l, sum2 += l * l, ++n;
        }
      const double mean = sum / n;
      return std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean;
    };
    const double fine = cv(0.025), coarse = cv(10);
    std::printf("%-12s variation: within 1 m %.3f, over 400 m %.3f\n", name, fine, coarse);
    EXPECT_GT(coarse, 0.03) << name;
    if (std::string(name) == "sandy") {
      double sum = 0;
      for (int i = 0; i < 400; ++i)
        sum += lum(gen::Albedo(m, noise, Eigen::Vector3f(i * 3.1f, i * 1.7f, 0)));
      EXPECT_GT(sum / 400, 0.28);
      EXPECT_LT(sum / 400, 0.45);
    }
  }
  EXPECT_EQ(gen::FindMaterial("metal", "test").metallic, 1.f);
  EXPECT_EQ(gen::FindMaterial("MetalGold", "test").metallic, 1.f);
  EXPECT_EQ(gen::FindMaterial("painted_red", "test").metallic, 0.f);
  EXPECT_GT(gen::FindMaterial("painted_red", "test").specular, 0.f);
}

}  // namespace
}  // namespace lsds
