// Analytic pixel bundles built by hand: known mixing, exact expected figures.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "bundles/bundle_stats.h"
#include "libs/exr/deep_image.h"
#include "libs/util/error.h"

namespace lsds::bundle {
namespace {

constexpr float kSky = std::numeric_limits<float>::infinity();

struct Sample {
  uint32_t instance = 0;
  uint32_t cls = 0;
  float z = kSky;
  float nx = 0, ny = 0, nz = 0;
};
using Pixel = std::vector<Sample>;

// Row-major pixels into a deep image with the bundle channels.
exr::DeepImage MakeBundle(int width, int height, const std::vector<Pixel>& pixels) {
  std::vector<uint32_t> counts;
  for (const Pixel& p : pixels) counts.push_back(static_cast<uint32_t>(p.size()));
  exr::DeepImage image(width, height, counts);
  auto& inst = image.AddChannel("instanceid", exr::PixelType::kUint).uints;
  auto& cls = image.AddChannel("classid", exr::PixelType::kUint).uints;
  auto& z = image.AddChannel("Z", exr::PixelType::kFloat).floats;
  auto& nx = image.AddChannel("NX", exr::PixelType::kFloat).floats;
  auto& ny = image.AddChannel("NY", exr::PixelType::kFloat).floats;
  auto& nz = image.AddChannel("NZ", exr::PixelType::kFloat).floats;
  size_t i = 0;
  for (const Pixel& p : pixels) {
    for (const Sample& s : p) {
      inst[i] = s.instance;
      cls[i] = s.cls;
      z[i] = s.z;
      nx[i] = s.nx;
      ny[i] = s.ny;
      nz[i] = s.nz;
      ++i;
    }
  }
  return image;
}

const Sample kBox{5, 2, 10.0f, 0, 0, 1};
const Sample kGround{1000, 1, 20.0f, 0, 0, 1};

TEST(BundleStats, HalfCoveredPixelIsMixedWithPurityAndCoverageOneHalf) {
  // 4 samples: the box covers the left half, the ground the right half.
  const exr::DeepImage image = MakeBundle(1, 1, {{kBox, kGround, kBox, kGround}});
  PixelMaps maps;
  const BundleStats s = AnalyzeFrame(image, StatsOptions(), &maps);
  EXPECT_EQ(s.pixels, 1u);
  EXPECT_EQ(s.mixed_pixels, 1u);
  EXPECT_EQ(static_cast<double>(s.mixed_pixels) / s.pixels, 1.0);
  EXPECT_EQ(maps.mixed[0], 1);
  EXPECT_EQ(maps.purity[0], 0.5f);
  EXPECT_EQ(s.purity_sum, 0.5);
  ASSERT_EQ(maps.coverage_counts[0], 2u);
  EXPECT_EQ(maps.coverage[0], 0.5f);
  EXPECT_EQ(maps.coverage[1], 0.5f);
  // A tie goes to the id of sample 0, the one nearest the centre.
  EXPECT_EQ(maps.majority_instance[0], 5u);
  EXPECT_EQ(maps.majority_class[0], 2u);
  EXPECT_EQ(maps.coverage_instance[0], 5u);
  EXPECT_EQ(maps.coverage_instance[1], 1000u);
  EXPECT_DOUBLE_EQ(s.entropy_sum, 1.0);  // two equal shares: one bit
  EXPECT_EQ(maps.edge[0], 1);
  EXPECT_EQ(s.per_class.at(1).mixed, 1u);
  EXPECT_EQ(s.per_class.at(2).mixed, 1u);
  EXPECT_EQ(s.objects.at(5).pixels, 1u);
  EXPECT_EQ(s.objects.at(5).mixed, 1u);
  // Purity 0.5 lands in bin [0.5, 0.6) of ten.
  EXPECT_EQ(s.purity_histogram[5], 1u);
}

TEST(BundleStats, OneHalfCoveredPixelAmongFourGivesMixedFractionOneQuarter) {
  const Pixel pure(4, kGround);
  const exr::DeepImage image = MakeBundle(2, 2, {pure, {kGround, kBox, kBox, kGround}, pure, pure});
  PixelMaps maps;
  const BundleStats s = AnalyzeFrame(image, StatsOptions(), &maps);
  EXPECT_EQ(s.pixels, 4u);
  EXPECT_EQ(s.mixed_pixels, 1u);
  EXPECT_EQ(maps.mixed, (std::vector<uint8_t>{0, 1, 0, 0}));
  EXPECT_EQ(maps.purity[1], 0.5f);
  EXPECT_EQ(maps.majority_instance[1], 1000u);  // tie: sample 0 wins
  EXPECT_EQ(s.per_class.at(1).pixels, 4u);
  EXPECT_EQ(s.per_class.at(1).mixed, 1u);
  EXPECT_EQ(s.per_class.at(2).pixels, 1u);
}

TEST(BundleStats, UniformRegionHasNoMixedPixels) {
  const exr::DeepImage image = MakeBundle(8, 8, std::vector<Pixel>(64, Pixel(4, kGround)));
  PixelMaps maps;
  const BundleStats s = AnalyzeFrame(image, StatsOptions(), &maps);
  EXPECT_EQ(s.pixels, 64u);
  EXPECT_EQ(s.samples, 256u);
  EXPECT_EQ(s.mixed_pixels, 0u);
  EXPECT_EQ(s.class_mixed_pixels, 0u);
  EXPECT_EQ(s.flying_pixels, 0u);
  EXPECT_EQ(s.purity_sum, 64.0);
  EXPECT_EQ(s.purity_histogram.back(), 64u);
  EXPECT_EQ(s.entropy_sum, 0.0);
  EXPECT_EQ(s.depth_spread_max, 0.0);
  EXPECT_EQ(s.normal_spread_max, 0.0);
  EXPECT_EQ(s.class_mixing.size(), 1u);
  EXPECT_EQ(s.class_mixing.at({1, 1}), 256u);
  for (size_t p = 0; p < 64; ++p) {
    EXPECT_EQ(maps.mixed[p], 0);
    EXPECT_EQ(maps.edge[p], 0);
    EXPECT_EQ(maps.coverage_counts[p], 1u);
  }
  EXPECT_EQ(s.objects.at(1000).pixels, 64u);
  EXPECT_EQ(s.objects.at(1000).mixed, 0u);
}

TEST(BundleStats, AveragedDepthFliesWhenSamplesAreFarApartNotWhenClose) {
  Sample near = kBox, far = kBox;
  far.z = 30.0f;  // same object, a depth step: averaged depth 20 lies in empty
                  // space
  Sample close = kBox;
  close.z = 10.02f;  // 2 cm apart: averaged depth 10.01 within 0.05 of both
  const exr::DeepImage image =
      MakeBundle(2, 1, {{near, near, far, far}, {near, near, close, close}});
  PixelMaps maps;
  const BundleStats s = AnalyzeFrame(image, StatsOptions(), &maps);
  EXPECT_EQ(s.flying_pixels, 1u);
  EXPECT_EQ(s.depth_pixels, 2u);
  EXPECT_EQ(s.mixed_pixels,
            0u);  // one instance: not mixed, yet its depth is uncertain
  EXPECT_EQ(maps.edge, (std::vector<uint8_t>{1, 0}));
  EXPECT_NEAR(s.depth_spread_max, 20.0, 1e-6);
}

TEST(BundleStats, FlyingThresholdIsTheLargerOfAbsoluteAndRelative) {
  Sample a = kBox, b = kBox;
  a.z = 100.0f;
  b.z = 101.0f;  // averaged 100.5, 0.5 from both samples
  const exr::DeepImage image = MakeBundle(1, 1, {{a, b}});
  StatsOptions relative;  // 1% of 100.5 = 1.005 > 0.5: not flying
  EXPECT_EQ(AnalyzeFrame(image, relative).flying_pixels, 0u);
  StatsOptions absolute;
  absolute.flying_relative = 0;
  absolute.flying_absolute = 0.1;  // 0.5 > 0.1: flying
  EXPECT_EQ(AnalyzeFrame(image, absolute).flying_pixels, 1u);
}

TEST(BundleStats, SkySamplesDoNotEnterTheAveragedDepth) {
  Sample sky;  // instance 0, class 0, +inf
  const exr::DeepImage image = MakeBundle(2, 1, {{kBox, sky, sky, sky}, {sky, sky}});
  const BundleStats s = AnalyzeFrame(image, StatsOptions());
  EXPECT_EQ(s.mixed_pixels, 1u);
  EXPECT_EQ(s.depth_pixels, 0u);  // one finite depth only
  EXPECT_EQ(s.flying_pixels, 0u);
  EXPECT_EQ(s.sky_only.pixels, 1u);
  EXPECT_EQ(s.by_distance[2].pixels, 1u);  // nearest depth 10 -> band [10, 20)
  EXPECT_EQ(s.objects.count(0), 0u);       // background is not an object
}

TEST(BundleStats, ClassMixingMatrixCountsSamples) {
  const exr::DeepImage image = MakeBundle(1, 1, {{kGround, kGround, kGround, kBox}});
  const BundleStats s = AnalyzeFrame(image, StatsOptions());
  EXPECT_EQ(s.class_mixing.at({1, 2}),
            3u);  // ground samples in pixels shared with boxes
  EXPECT_EQ(s.class_mixing.at({2, 1}), 1u);
  EXPECT_EQ(s.class_mixing.count({1, 1}), 0u);
}

TEST(BundleStats, NormalSpreadIsTheLargestAngleToTheMeanNormal) {
  Sample up = kBox, side = kBox;
  side.nz = 0;
  side.nx = 1;  // 90 degrees from up: the mean lies 45 degrees from both
  const exr::DeepImage image = MakeBundle(1, 1, {{up, side}});
  const BundleStats s = AnalyzeFrame(image, StatsOptions());
  EXPECT_EQ(s.normal_pixels, 1u);
  EXPECT_NEAR(s.normal_spread_max, 45.0, 1e-9);
}

TEST(BundleStats, EmptyPixelsAreCountedApart) {
  const exr::DeepImage image = MakeBundle(2, 1, {{}, {kBox}});
  PixelMaps maps;
  const BundleStats s = AnalyzeFrame(image, StatsOptions(), &maps);
  EXPECT_EQ(s.empty_pixels, 1u);
  EXPECT_EQ(s.pixels, 1u);
  EXPECT_EQ(maps.coverage_counts[0], 0u);
  EXPECT_EQ(maps.purity[0], 0.0f);
}

TEST(BundleStats, MergeAddsFramesAndObjectSizeBins) {
  const exr::DeepImage image = MakeBundle(2, 1, {{kBox, kGround, kBox, kGround}, Pixel(4, kBox)});
  const BundleStats one = AnalyzeFrame(image, StatsOptions());
  BundleStats total;
  total.Merge(one);
  total.Merge(one);
  EXPECT_EQ(total.frames, 2);
  EXPECT_EQ(total.pixels, 4u);
  EXPECT_EQ(total.mixed_pixels, 2u);
  EXPECT_EQ(total.objects.at(5).frames, 2u);
  EXPECT_EQ(total.objects.at(5).pixels, 4u);
  EXPECT_EQ(total.objects.at(5).mixed, 2u);
  // Object 5 has 2 pixels per frame, one mixed: size bin [1, 16), share 0.5
  // each time.
  EXPECT_EQ(total.by_object_size[0].objects, 4u);  // box and ground, twice
  EXPECT_DOUBLE_EQ(total.by_object_size[0].share_sum, 0.5 + 0.5 + 1.0 + 1.0);
}

TEST(BundleStats, MissingIdChannelIsAnError) {
  exr::DeepImage image(1, 1, {1});
  image.AddChannel("Z", exr::PixelType::kFloat);
  EXPECT_THROW(AnalyzeFrame(image, StatsOptions()), Error);
}

}  // namespace
}  // namespace lsds::bundle
