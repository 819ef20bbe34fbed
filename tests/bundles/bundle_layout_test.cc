// The compact and residual bundle layouts (docs/format.md "Pixel bundles"):
// lossless against the full layout sample for sample, read by the one reader
// for all, and, end to end, `lsds bundles` statistics identical for a
// collection generated in any layout.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/collection/bundle_layout.h"
#include "libs/collection/bundle_residual.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/exr_info.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "tests/build_paths.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using exr::DeepImage;
using exr::PixelType;

class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() / ("lsds_bundle_layout_test_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

int RunLsds(const std::string& args, std::string* output) {
  const std::string out_file =
      (fs::temp_directory_path() / ("lsds_layout_cli_out_" + std::to_string(getpid()) + ".txt"))
          .string();
  const std::string command =
      ::lsds::testing::BinaryDir() + "/tools/lsds " + args + " > " + out_file + " 2>&1";
  const int status = std::system(command.c_str());
  *output = ReadFile(out_file);
  fs::remove(out_file);
  return WEXITSTATUS(status);
}

exr::WriteOptions Zips() {
  exr::WriteOptions options;
  options.compression = exr::Compression::kZips;  // deep files allow none, rle, zips
  return options;
}

uint32_t Bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// Every channel of `a` equals `b`'s bit for bit (NaN and -0 included).
void ExpectSameSamples(const DeepImage& a, const DeepImage& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  ASSERT_EQ(a.sample_counts(), b.sample_counts());
  ASSERT_EQ(a.channels().size(), b.channels().size());
  for (const exr::DeepChannel& ca : a.channels()) {
    const exr::DeepChannel& cb = b.Get(ca.name);
    ASSERT_EQ(ca.type, cb.type) << ca.name;
    EXPECT_EQ(ca.uints, cb.uints) << ca.name;
    ASSERT_EQ(ca.floats.size(), cb.floats.size()) << ca.name;
    size_t differ = 0;
    for (size_t i = 0; i < ca.floats.size(); ++i)
      differ += Bits(ca.floats[i]) != Bits(cb.floats[i]);
    EXPECT_EQ(differ, 0u) << ca.name;
  }
}

// A full bundle of w x h pixels with the sampling rule's positions: sky in the
// top rows (all samples equal), a tilted plane (same id, depths differ), and a
// few mixed pixels, with -0, NaN-free infinities and one object per class.
DeepImage FullBundle(int w, int h, const BundleSampling& sampling) {
  const int spp = sampling.sampler.spp;
  DeepImage image(w, h, std::vector<uint32_t>(static_cast<size_t>(w) * h, spp));
  for (const exr::ChannelSpec& spec : FullBundleChannels()) image.AddChannel(spec.name, spec.type);
  auto& inst = image.Get("instanceid").uints;
  auto& cls = image.Get("classid").uints;
  auto& z = image.Get("Z").floats;
  auto& nx = image.Get("NX").floats;
  auto& nz = image.Get("NZ").floats;
  auto& sx = image.Get("SX").floats;
  auto& sy = image.Get("SY").floats;
  std::vector<Eigen::Vector2d> positions(spp);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      PixelSamples(sampling.sampler, sampling.frame, x, y, positions.data());
      const uint64_t first = image.FirstSample(x, y);
      for (int k = 0; k < spp; ++k) {
        const uint64_t s = first + k;
        sx[s] = static_cast<float>(positions[k].x() - x);
        sy[s] = static_cast<float>(positions[k].y() - y);
        if (y < 2) {  // sky
          z[s] = INFINITY;
          nx[s] = -0.0f;
          continue;
        }
        const bool on_box = x >= 5 && x < 9 && (x > 5 || positions[k].x() - x > 0.5);
        inst[s] = on_box ? 7 : 1;
        cls[s] = on_box ? 3 : 1;
        z[s] = on_box ? 10.0f : static_cast<float>(20.0 + 0.1 * positions[k].y());
        nz[s] = 1.0f;
        if (y == 2) z[s] = 20.0f;  // a flat row: pure and identical, collapses
      }
    }
  }
  return image;
}

TEST(BundleLayout, CompactReadsBackExactlyTheFullSamples) {
  TempDir dir;
  const BundleSampling sampling{{4, 1.0, 99}, 5, std::nullopt};
  const DeepImage full = FullBundle(12, 6, sampling);
  WriteBundleExr(dir.path() / "full.exr", full, BundleLayout::kFull, sampling, Zips());
  WriteBundleExr(dir.path() / "compact.exr", full, BundleLayout::kCompact, sampling, Zips());

  const exr::ExrInfo info = exr::ReadExrInfo(dir.path() / "compact.exr");
  EXPECT_EQ(info.attributes.at(kBundleLayoutAttribute), "compact");
  EXPECT_EQ(info.Find("SX"), nullptr);       // positions derived
  EXPECT_EQ(info.Find("classid"), nullptr);  // a function of instanceid
  EXPECT_EQ(ReadableChannels(info).size(), FullBundleChannels().size());
  // Sky rows and the flat row store one sample per pixel.
  const DeepImage stored = exr::ReadDeepExr(dir.path() / "compact.exr");
  EXPECT_EQ(stored.SampleCount(0, 0), 1u);
  EXPECT_EQ(stored.SampleCount(0, 2), 1u);
  EXPECT_EQ(stored.SampleCount(0, 3), 4u);  // depths differ on the tilt
  EXPECT_EQ(stored.SampleCount(5, 2), 4u);  // mixed: box and ground

  ExpectSameSamples(ReadBundleExr(dir.path() / "compact.exr"), full);
  ExpectSameSamples(ReadBundleExr(dir.path() / "full.exr"), full);
  // A subset, in the order asked, the same from both.
  const std::vector<std::string> some = {"classid", "SY", "Z"};
  ExpectSameSamples(ReadBundleExr(dir.path() / "compact.exr", some),
                    ReadBundleExr(dir.path() / "full.exr", some));
}

TEST(BundleLayout, KeepsWhatItCannotDerive) {
  TempDir dir;
  const BundleSampling sampling{{4, 0.5, 3}, 0, std::nullopt};
  DeepImage full = FullBundle(8, 4, sampling);
  // Instance 7 of two classes: classid must stay a channel.
  full.Get("classid").uints[full.FirstSample(5, 3)] = 4;
  WriteBundleExr(dir.path() / "a.exr", full, BundleLayout::kCompact, sampling, Zips());
  EXPECT_NE(exr::ReadExrInfo(dir.path() / "a.exr").Find("classid"), nullptr);
  ExpectSameSamples(ReadBundleExr(dir.path() / "a.exr"), full);
  // Positions that are not the rule's (another frame's): the full layout.
  BundleSampling other = sampling;
  other.frame = 1;
  WriteBundleExr(dir.path() / "b.exr", full, BundleLayout::kCompact, other, Zips());
  const exr::ExrInfo info = exr::ReadExrInfo(dir.path() / "b.exr");
  EXPECT_EQ(info.attributes.count(kBundleLayoutAttribute), 0u);
  EXPECT_NE(info.Find("SX"), nullptr);
  ExpectSameSamples(ReadBundleExr(dir.path() / "b.exr"), full);
}

// A camera looking down at 30 degrees from vertical, for the residual layout.
BundleView TestView(int w, int h, DepthKind kind) {
  BundleView view;
  view.intrinsics = PinholeCamera::FromHorizontalFov(w, h, 60);
  const double a = 150 * M_PI / 180;  // optical axis 30 degrees off straight down
  view.cam_from_world_rotation << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a),
      std::cos(a);
  view.depth_kind = kind;
  return view;
}

TEST(BundleLayout, ResidualReadsBackExactlyTheFullSamples) {
  TempDir dir;
  BundleSampling sampling{{4, 1.0, 99}, 5, std::nullopt};
  const DeepImage full = FullBundle(12, 6, sampling);
  WriteBundleExr(dir.path() / "full.exr", full, BundleLayout::kFull, sampling, Zips());
  for (const DepthKind kind : {DepthKind::kPlanar, DepthKind::kPerspective}) {
    sampling.view = TestView(12, 6, kind);
    WriteBundleExr(dir.path() / "residual.exr", full, BundleLayout::kResidual, sampling, Zips());
    const exr::ExrInfo info = exr::ReadExrInfo(dir.path() / "residual.exr");
    EXPECT_EQ(info.attributes.at(kBundleLayoutAttribute), "residual");
    for (const char* stored : {"dZ", "dNX", "dNY", "dNZ", "instanceid"}) {
      ASSERT_NE(info.Find(stored), nullptr) << stored;
      EXPECT_EQ(info.Find(stored)->type, PixelType::kUint) << stored;
    }
    EXPECT_EQ(info.Find("Z"), nullptr);
    EXPECT_EQ(info.Find("SX"), nullptr);
    EXPECT_EQ(info.Find("classid"), nullptr);
    // What a reader gets: the full layout's channels and types.
    std::vector<exr::ChannelSpec> expected = FullBundleChannels();
    std::sort(expected.begin(), expected.end(), [](const auto& a, const auto& b) {
      return a.name < b.name;
    });
    const std::vector<exr::ChannelSpec> readable = ReadableChannels(info);
    ASSERT_EQ(readable.size(), expected.size());
    for (size_t i = 0; i < readable.size(); ++i) {
      EXPECT_EQ(readable[i].name, expected[i].name);
      EXPECT_EQ(readable[i].type, expected[i].type) << readable[i].name;
    }
    // Every pixel keeps its samples (no collapse), and all of them read back.
    EXPECT_EQ(exr::ReadDeepExr(dir.path() / "residual.exr").SampleCount(0, 0), 4u);
    ExpectSameSamples(ReadBundleExr(dir.path() / "residual.exr"), full);
    // Subsets: the depth alone (its prediction decodes the normals it needs
    // without returning them), one normal alone.
    for (const std::vector<std::string>& some :
         {std::vector<std::string>{"Z"}, {"NY"}, {"classid", "SY", "Z", "NX"}}) {
      ExpectSameSamples(ReadBundleExr(dir.path() / "residual.exr", some),
                        ReadBundleExr(dir.path() / "full.exr", some));
    }
  }
}

// The prediction the layout relies on: on a plane, the depth of any position
// follows from one sample's depth and normal, to float rounding.
TEST(BundleLayout, PlanePredictionIsExactOnAPlane) {
  for (const DepthKind kind : {DepthKind::kPlanar, DepthKind::kPerspective}) {
    const BundleView view = TestView(640, 480, kind);
    const PlaneDepthPredictor predictor(view);
    // The ground plane z = 0 seen from (0, -20, 30).
    const Eigen::Vector3d centre(0, -20, 30), normal(0, 0, 1);
    const Eigen::Matrix3d world_from_cam = view.cam_from_world_rotation.transpose();
    auto depth_at = [&](const Eigen::Vector2d& pixel) {
      const Eigen::Vector3d ray = view.intrinsics.CamFromImage(pixel);  // z == 1
      const Eigen::Vector3d dir = world_from_cam * ray;
      const double t = -centre.z() / dir.z();  // planar depth: the z == 1 ray's scale
      return kind == DepthKind::kPlanar ? t : t * ray.norm();
    };
    const float n[3] = {0, 0, 1};
    for (const auto& [from, to] : std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>{
             {{320.5, 300.5}, {321.5, 300.5}},
             {{10.5, 470.5}, {10.9, 470.1}},
             {{600.5, 250.5}, {600.5, 251.5}}}) {
      const double truth = depth_at(to);
      const float predicted = predictor.Predict(static_cast<float>(depth_at(from)), n, from, to);
      EXPECT_NEAR(predicted, truth, 4e-7 * truth) << from.transpose() << " -> " << to.transpose();
    }
    // Undefined predictions fall back to the reference depth.
    const float zero[3] = {0, 0, 0};
    EXPECT_EQ(predictor.Predict(12.5f, zero, {1.5, 1.5}, {2.5, 1.5}), 12.5f);
    EXPECT_TRUE(std::isinf(predictor.Predict(INFINITY, n, {1.5, 1.5}, {2.5, 1.5})));
  }
}

TEST(BundleLayout, ResidualWithoutAViewWritesCompact) {
  TempDir dir;
  const BundleSampling sampling{{4, 1.0, 2}, 0, std::nullopt};
  const DeepImage full = FullBundle(8, 4, sampling);
  WriteBundleExr(dir.path() / "a.exr", full, BundleLayout::kResidual, sampling, Zips());
  EXPECT_EQ(exr::ReadExrInfo(dir.path() / "a.exr").attributes.at(kBundleLayoutAttribute),
            "compact");
  ExpectSameSamples(ReadBundleExr(dir.path() / "a.exr"), full);
}

TEST(BundleLayout, BadResidualHeadersAreErrorsNamingTheFileAndAttribute) {
  TempDir dir;
  BundleSampling sampling{{4, 1.0, 1}, 0, TestView(8, 4, DepthKind::kPlanar)};
  const DeepImage full = FullBundle(8, 4, sampling);
  WriteBundleExr(dir.path() / "good.exr", full, BundleLayout::kResidual, sampling, Zips());
  const exr::ExrInfo info = exr::ReadExrInfo(dir.path() / "good.exr");
  const DeepImage stored = exr::ReadDeepExr(dir.path() / "good.exr");
  struct Case {
    std::string attribute, value;  // empty value: removed
  };
  for (const Case& c : std::vector<Case>{{"lsdsBundleRotation", ""},
                                         {"lsdsBundleRotation", "1 0 0 0 1 0 0 0"},
                                         {"lsdsBundleIntrinsics", "100 100 4 x"},
                                         {"lsdsBundleDepthKind", "radial"}}) {
    exr::WriteOptions options = Zips();
    options.attributes = info.attributes;
    if (c.value.empty()) {
      options.attributes.erase(c.attribute);
    } else {
      options.attributes[c.attribute] = c.value;
    }
    exr::WriteDeepExr(dir.path() / "bad.exr", stored, options);
    try {
      ReadBundleExr(dir.path() / "bad.exr");
      FAIL() << "expected an error for " << c.attribute << " = '" << c.value << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("bad.exr"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.attribute), std::string::npos) << e.what();
    }
  }
  // A pixel with another sample count than the header's.
  std::vector<uint32_t> counts(32, 4);
  counts[9] = 1;
  DeepImage uneven(8, 4, counts);
  for (const char* c : {"instanceid", "dZ", "dNX", "dNY", "dNZ"}) {
    uneven.AddChannel(c, PixelType::kUint);
  }
  exr::WriteOptions options = Zips();
  options.attributes = info.attributes;
  exr::WriteDeepExr(dir.path() / "uneven.exr", uneven, options);
  try {
    ReadBundleExr(dir.path() / "uneven.exr");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("uneven.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pixel (1, 1)"), std::string::npos) << e.what();
  }
}

TEST(BundleLayout, BadCompactHeadersAreErrorsNamingTheFile) {
  TempDir dir;
  const BundleSampling sampling{{4, 1.0, 1}, 0, std::nullopt};
  const DeepImage full = FullBundle(8, 4, sampling);
  // A compact file whose class table lacks an instance it holds.
  DeepImage packed(8, 4, std::vector<uint32_t>(32, 1));
  packed.AddChannel("instanceid", PixelType::kUint).uints.assign(32, 5);
  for (const char* c : {"Z", "NX", "NY", "NZ"}) packed.AddChannel(c, PixelType::kFloat);
  exr::WriteOptions options = Zips();
  options.attributes = {{kBundleLayoutAttribute, "compact"},
                        {"lsdsSamplesPerPixel", "4"},
                        {"lsdsSamplingSeed", "1"},
                        {"lsdsSamplingFrame", "0"},
                        {"lsdsSamplingJitter", "1"},
                        {"lsdsClassOfInstance", "0:0 1:1"}};
  exr::WriteDeepExr(dir.path() / "bad.exr", packed, options);
  try {
    ReadBundleExr(dir.path() / "bad.exr");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pixel (0, 0)"), std::string::npos) << e.what();
  }
  options.attributes["lsdsSamplesPerPixel"] = "five";
  exr::WriteDeepExr(dir.path() / "bad2.exr", packed, options);
  EXPECT_THROW(ReadBundleExr(dir.path() / "bad2.exr"), Error);
}

// End to end as a user meets it: the demo scene generated in the full, the
// compact and the default (residual) layout; all validate, read the same
// samples and give the same `lsds bundles` statistics, and each layout's
// bundle files are smaller than the one before.
TEST(BundleLayout, GeneratedCollectionsGiveIdenticalStatistics) {
  TempDir dir;
  std::string out;
  const std::string common = " --demo --demo-size 64x48 --demo-frames 3 --seed 4 --quiet -o ";
  const fs::path full = dir.path() / "full", compact = dir.path() / "compact",
                 residual = dir.path() / "residual";
  ASSERT_EQ(RunLsds("generate --bundle-layout full" + common + full.string(), &out), 0) << out;
  ASSERT_EQ(RunLsds("generate --bundle-layout compact" + common + compact.string(), &out), 0)
      << out;
  ASSERT_EQ(RunLsds("generate" + common + residual.string(), &out), 0) << out;
  nlohmann::json stats[3];
  int i = 0;
  for (const fs::path& root : {full, compact, residual}) {
    EXPECT_EQ(RunLsds("validate --fail-on warning " + root.string(), &out), 0) << root << "\n"
                                                                               << out;
    EXPECT_EQ(RunLsds("bundles " + root.string() + " -o " + root.string() + ".json", &out), 0)
        << out;
    stats[i] = nlohmann::json::parse(ReadFile(root.string() + ".json"));
    stats[i++].erase("collection");
  }
  EXPECT_GT(stats[0]["summary"]["mixed_pixels"].get<uint64_t>(), 0u);
  EXPECT_EQ(stats[0], stats[1]);
  EXPECT_EQ(stats[0], stats[2]);

  const CollectionReader rf(full), rc(compact), rr(residual);
  EXPECT_EQ(rf.header().FindLayerBySemantic("bundle")->layout, BundleLayout::kFull);
  EXPECT_EQ(rc.header().FindLayerBySemantic("bundle")->layout, BundleLayout::kCompact);
  EXPECT_EQ(rr.header().FindLayerBySemantic("bundle")->layout, BundleLayout::kResidual);
  uintmax_t full_bytes = 0, compact_bytes = 0, residual_bytes = 0;
  std::vector<Frame> frames;
  rf.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  for (const Frame& frame : frames) {
    const DeepImage expected = rf.ReadDeepLayer(frame, "bundle", {});
    ExpectSameSamples(rc.ReadDeepLayer(frame, "bundle", {}), expected);
    ExpectSameSamples(rr.ReadDeepLayer(frame, "bundle", {}), expected);
    full_bytes += fs::file_size(rf.LayerPath(frame, "bundle"));
    compact_bytes += fs::file_size(rc.LayerPath(frame, "bundle"));
    residual_bytes += fs::file_size(rr.LayerPath(frame, "bundle"));
  }
  EXPECT_LT(compact_bytes, full_bytes);
  EXPECT_LT(residual_bytes, compact_bytes);
}

}  // namespace
}  // namespace lsds
