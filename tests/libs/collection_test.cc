#include <fstream>

#include <gtest/gtest.h>

#include "libs/collection/bundle_layout.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/collection/json_io.h"
#include "libs/collection/sample_positions.h"
#include "libs/collection/schema.h"
#include "libs/exr/exr_info.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "synth/synthetic_collection.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

using nlohmann::json;

CollectionHeader SampleHeader(int64_t frames) {
  CollectionHeader header;
  header.provenance.generator = "test";
  header.provenance.generator_version = "1";
  header.provenance.seed = 42;
  header.provenance.scene_source = "LSCENE = ONE(S)";
  header.classes = {{1, "ground"}, {7, "barrel"}};
  header.layers = {StandardLayer("depth", DepthKind::kPerspective), StandardLayer("bundle")};
  header.metadata = {{"metadata.json", false, ""}};
  header.frame_count = frames;
  return header;
}

Frame SampleFrame(int64_t index) {
  Frame frame;
  frame.index = index;
  frame.time = 0.5 * index;
  frame.sequence = "P1(1)";
  frame.camera.intrinsics = PinholeCamera::FromHorizontalFov(64, 48, 50);
  frame.camera.cam_from_world_rotation =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  frame.camera.cam_from_world_translation = {1.25, -2.5, 30.125};
  frame.files = {{"depth", "depth/" + std::to_string(index) + ".exr"}};
  ObjectTruth object;
  object.instance_id = 3;
  object.class_id = 7;
  object.name = "O2#1";
  object.obb.emplace();
  object.obb->center = {1, 2, 0.5};
  object.obb->half_extents = {0.3, 0.3, 0.5};
  object.bbox = Box2d{10, 11, 20, 31};
  // Format 1.2's oriented boxes, with doubles that need every digit.
  object.bbox_oriented = OrientedBox2d{{Eigen::Vector2d(10.1, 11),
                                        Eigen::Vector2d(20, 12.3),
                                        Eigen::Vector2d(18.7, 31),
                                        Eigen::Vector2d(8.8, 29.7)}};
  object.bbox_oriented_projected = OrientedBox2d{{Eigen::Vector2d(1.0 / 3, -2.5),
                                                  Eigen::Vector2d(21.25, 0.1),
                                                  Eigen::Vector2d(19.0, 33.0 / 7),
                                                  Eigen::Vector2d(-1e-7, 30)}};
  object.visible_pixels = 150;
  object.visibility = 0.75;
  object.in_frame = 1.0;
  frame.objects.push_back(object);
  ObjectTruth hidden = object;
  hidden.instance_id = 4;
  hidden.bbox.reset();
  hidden.bbox_oriented.reset();
  hidden.visible_pixels = 0;
  hidden.visibility = 0;
  frame.objects.push_back(hidden);
  // Format 1.2: an imported object its source gives only a 2D box for.
  ObjectTruth flat = object;
  flat.instance_id = 5;
  flat.obb.reset();
  flat.bbox_projected.reset();
  flat.bbox_oriented_projected.reset();
  frame.objects.push_back(flat);
  return frame;
}

TEST(CollectionJson, WriteReadRoundTrip) {
  testing::TempDir dir;
  CollectionWriter writer(dir.path(), SampleHeader(3));
  for (int k = 0; k < 3; ++k) writer.Append(SampleFrame(k));
  writer.Commit();

  const CollectionReader reader(dir.path());
  EXPECT_EQ(reader.frames_in_file(), 3u);
  const CollectionHeader& header = reader.header();
  EXPECT_EQ(header.provenance.seed, 42u);
  EXPECT_EQ(header.classes.size(), 2u);
  ASSERT_NE(header.FindLayer("depth"), nullptr);
  EXPECT_EQ(header.FindLayer("depth")->depth_kind, DepthKind::kPerspective);
  EXPECT_TRUE(header.FindLayer("bundle")->deep);
  int seen = 0;
  reader.ForEachFrame([&](const Frame& frame) {
    const Frame expected = SampleFrame(seen);
    EXPECT_EQ(FrameToJson(frame),
              FrameToJson(expected));  // exact doubles survive
    EXPECT_EQ(frame.objects[0].bbox->x1, 20);
    EXPECT_FALSE(frame.objects[1].bbox);
    ASSERT_TRUE(frame.objects[0].bbox_oriented && frame.objects[0].bbox_oriented_projected);
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(frame.objects[0].bbox_oriented->corners[i],
                expected.objects[0].bbox_oriented->corners[i]);
      EXPECT_EQ(frame.objects[0].bbox_oriented_projected->corners[i],
                expected.objects[0].bbox_oriented_projected->corners[i]);
    }
    EXPECT_FALSE(frame.objects[1].bbox_oriented);  // absent, not null
    ASSERT_EQ(frame.objects.size(), 3u);
    EXPECT_TRUE(frame.objects[0].obb);
    EXPECT_FALSE(frame.objects[2].obb);  // absent: no 3D box
    EXPECT_EQ(frame.objects[2].bbox, expected.objects[2].bbox);
    ++seen;
  });
  EXPECT_EQ(seen, 3);
}

TEST(CollectionJson, WriterRefusesWrongFrameCount) {
  testing::TempDir dir;
  CollectionWriter writer(dir.path(), SampleHeader(2));
  writer.Append(SampleFrame(0));
  EXPECT_THROW(writer.Commit(), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "collection.json"));
}

TEST(Schema, RejectsUnknownKeyWithPointer) {
  json header = HeaderToJson(SampleHeader(0));
  header["conventions"]["handednes"] = "right";
  const auto issues = JsonSchema::Get("collection.schema.json").Validate(header);
  ASSERT_FALSE(issues.empty());
  EXPECT_EQ(issues[0].pointer, "/conventions/handednes");
}

TEST(Schema, RejectsWrongTypeInFrameWithPointer) {
  json frame = FrameToJson(SampleFrame(0));
  frame["objects"][1]["visibility"] = 1.5;
  const auto issues =
      JsonSchema::Get("collection.schema.json", "frame").Validate(frame, "/frames/9");
  ASSERT_FALSE(issues.empty());
  EXPECT_EQ(issues[0].pointer, "/frames/9/objects/1/visibility");
}

// An object without a 3D box has no "obb" key, and the schema accepts it; a present obb is still
// checked.
TEST(Schema, TheObbIsOptional) {
  json frame = FrameToJson(SampleFrame(0));
  const JsonSchema& schema = JsonSchema::Get("collection.schema.json", "frame");
  EXPECT_FALSE(frame["objects"][2].contains("obb"));
  EXPECT_TRUE(frame["objects"][0].contains("obb"));
  EXPECT_TRUE(schema.Validate(frame, "/frames/0").empty());
  frame["objects"][0]["obb"].erase("center");
  const auto issues = schema.Validate(frame, "/frames/0");
  ASSERT_FALSE(issues.empty());
  EXPECT_EQ(issues[0].pointer, "/frames/0/objects/0/obb");
}

TEST(Schema, OrientedBoxesAreFourPointPairs) {
  json frame = FrameToJson(SampleFrame(0));
  const JsonSchema& schema = JsonSchema::Get("collection.schema.json", "frame");
  EXPECT_TRUE(schema.Validate(frame, "/frames/0").empty());
  EXPECT_EQ(frame["objects"][0]["bbox_oriented"].size(), 4u);
  EXPECT_FALSE(frame["objects"][1].contains("bbox_oriented"));
  frame["objects"][0]["bbox_oriented"].erase(3);
  const auto three = schema.Validate(frame, "/frames/0");
  ASSERT_FALSE(three.empty());
  EXPECT_EQ(three[0].pointer, "/frames/0/objects/0/bbox_oriented");
  frame = FrameToJson(SampleFrame(0));
  frame["objects"][0]["bbox_oriented_projected"][2] = json::array({1, 2, 3});
  const auto triple = schema.Validate(frame, "/frames/0");
  ASSERT_FALSE(triple.empty());
  EXPECT_EQ(triple[0].pointer, "/frames/0/objects/0/bbox_oriented_projected/2");
}

TEST(Schema, ReaderNamesFileAndPointer) {
  testing::TempDir dir;
  json header = HeaderToJson(SampleHeader(1));
  json frame = FrameToJson(SampleFrame(0));
  frame["camera"]["fx"] = "wide";
  header["frames"] = json::array({frame});
  WriteFileAtomic(dir / "collection.json", header.dump());
  const CollectionReader reader(dir.path());  // the header is fine
  try {
    reader.ForEachFrame([](const Frame&) {});
    FAIL() << "expected a schema error";
  } catch (const Error& e) {
    EXPECT_EQ(e.location().json_pointer, "/frames/0/camera/fx");
    EXPECT_NE(std::string(e.what()).find("collection.json#/frames/0/camera/fx"), std::string::npos);
  }
}

TEST(CollectionJson, SyntaxErrorHasLineAndColumn) {
  testing::TempDir dir;
  std::ofstream(dir / "collection.json")
      << "{\n  \"format\": \"lsds-collection\",\n  \"frames\": [,]\n}\n";
  try {
    CollectionReader reader(dir.path());
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.location().line, 3);
    EXPECT_GT(e.location().column, 0);
  }
}

TEST(CollectionJson, NotACollection) {
  testing::TempDir dir;
  EXPECT_THROW(CollectionReader(dir.path()), Error);
  EXPECT_THROW(CollectionReader(dir / "nowhere"), Error);
}

TEST(CollectionJson, StreamingVisitsFramesInOrderWithoutHoldingThem) {
  testing::TempDir dir;
  const int frames = 500;
  CollectionWriter writer(dir.path(), SampleHeader(frames));
  for (int k = 0; k < frames; ++k) writer.Append(SampleFrame(k));
  writer.Commit();
  const CollectionReader reader(dir.path());
  int64_t expected = 0;
  reader.ForEachFrame([&](const Frame& frame) { EXPECT_EQ(frame.index, expected++); });
  EXPECT_EQ(expected, frames);
  std::atomic<int64_t> sum{0};
  reader.ParallelForEachFrame([&](const Frame& frame) { sum += frame.index; }, 16);
  EXPECT_EQ(sum.load(), int64_t{frames} * (frames - 1) / 2);
}

// synth::Spec::bundle_layout: at 1 sample per pixel the synthetic positions
// are the sampling rule's, so compact is written (marked in the file) and
// reads back the samples of the full layout; at 4 the pattern is not the
// rule's and the writer keeps the full layout, still declared compact-readable.
TEST(SyntheticCollection, CompactBundleReadsBackTheFullSamples) {
  testing::TempDir dir;
  for (int n : {1, 2}) {
    synth::Spec spec = synth::DefaultSpec();
    spec.width = 16, spec.height = 12;
    spec.samples_per_axis = n;
    const std::filesystem::path full = dir / ("full" + std::to_string(n)),
                                compact = dir / ("compact" + std::to_string(n));
    synth::WriteCollection(full, spec);
    spec.bundle_layout = BundleLayout::kCompact;
    synth::WriteCollection(compact, spec);
    const CollectionReader rf(full), rc(compact);
    EXPECT_EQ(rc.header().FindLayerBySemantic("bundle")->layout, BundleLayout::kCompact);
    std::vector<Frame> frames;
    rf.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
    ASSERT_EQ(frames.size(), 4u);
    for (const Frame& frame : frames) {
      const exr::ExrInfo info = exr::ReadExrInfo(rc.LayerPath(frame, "bundle"));
      EXPECT_EQ(info.attributes.count(kBundleLayoutAttribute), n == 1 ? 1u : 0u) << n;
      const exr::DeepImage a = rf.ReadDeepLayer(frame, "bundle", {});
      const exr::DeepImage b = rc.ReadDeepLayer(frame, "bundle", {});
      ASSERT_EQ(a.sample_counts(), b.sample_counts());
      for (const exr::ChannelSpec& c : FullBundleChannels()) {
        EXPECT_EQ(a.Get(c.name).uints, b.Get(c.name).uints) << c.name;
        EXPECT_EQ(a.Get(c.name).floats, b.Get(c.name).floats) << c.name;
      }
    }
  }
}

TEST(MetadataJson, SyntheticCollectionMetadataEqualsTruth) {
  testing::TempDir dir;
  synth::Spec spec = synth::DefaultSpec();
  spec.width = 16, spec.height = 12;
  synth::WriteCollection(dir / "c", spec);
  const CollectionReader collection(dir / "c");
  std::vector<Frame> frames;
  collection.ForEachFrame([&](const Frame& frame) { frames.push_back(frame); });
  const MetadataReader metadata(dir / "c" / "metadata.json");
  EXPECT_FALSE(metadata.header().perturbed);
  int k = 0;
  metadata.ForEachFrame([&](const MetadataFrame& m) {
    const Rigid3d cam_from_enu = CamFromEnu(m.position, m.attitude);
    EXPECT_TRUE(cam_from_enu.rotation.toRotationMatrix().isApprox(
        frames[k].camera.cam_from_world_rotation, 1e-12));
    EXPECT_TRUE(
        cam_from_enu.translation.isApprox(frames[k].camera.cam_from_world_translation, 1e-12));
    EXPECT_EQ(m.camera, frames[k].camera.intrinsics);
    ++k;
  });
  EXPECT_EQ(k, 4);
}

// docs/format.md's sample-position rule, transcribed from the text with its
// own splitmix64: the compact and residual layouts store no positions, so a
// collection written today must decode the same under any later code.
uint64_t DocSplitMix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  x ^= x >> 31;
  return x;
}
uint64_t DocH(uint64_t a, uint64_t b) { return DocSplitMix64(a ^ DocSplitMix64(b)); }
double DocU(uint64_t h) { return static_cast<double>(h >> 11) / 9007199254740992.0; }

std::vector<Eigen::Vector2d> DocPositions(
    int spp, double jitter, uint64_t seed, int64_t f, int x, int y) {
  int n = 1;
  while (n * n < spp) ++n;
  const uint64_t p =
      DocH(DocH(seed, static_cast<uint64_t>(f)), (static_cast<uint64_t>(y) << 32) | x);
  std::vector<Eigen::Vector2d> cells;
  for (int k = 0; k < spp; ++k) {
    const int cx = k % n, cy = k / n;
    const uint64_t hk = DocH(p, static_cast<uint64_t>(k));
    const double jx = jitter > 0 ? jitter * (DocU(hk) - 0.5) : 0;
    const double jy = jitter > 0 ? jitter * (DocU(DocH(hk, 1)) - 0.5) : 0;
    cells.emplace_back((cx + 0.5 + jx) / n, (cy + 0.5 + jy) / n);
  }
  size_t nearest = 0;
  for (size_t k = 1; k < cells.size(); ++k) {
    if ((cells[k] - Eigen::Vector2d(0.5, 0.5)).squaredNorm() <
        (cells[nearest] - Eigen::Vector2d(0.5, 0.5)).squaredNorm())
      nearest = k;
  }
  std::vector<Eigen::Vector2d> out = {Eigen::Vector2d(x + 0.5, y + 0.5)};
  for (size_t k = 0; k < cells.size(); ++k) {
    if (k != nearest) out.emplace_back(x + cells[k].x(), y + cells[k].y());
  }
  return out;
}

TEST(SamplePositions, FollowTheDocumentedRuleBitForBit) {
  for (int spp : {1, 4, 9, 16}) {
    for (double jitter : {0.0, 0.5, 1.0}) {
      for (int64_t frame : {int64_t{0}, int64_t{7}, int64_t{123456789}}) {
        const SamplerSettings settings{spp, jitter, 0xfeedbeefull};
        const FrameSampler sampler(settings, frame);
        ASSERT_EQ(sampler.spp(), spp);
        std::vector<Eigen::Vector2d> got(spp), single(spp);
        for (const auto& [x, y] : {std::pair{0, 0}, {1, 0}, {0, 1}, {37, 911}, {4095, 4095}}) {
          const std::vector<Eigen::Vector2d> want =
              DocPositions(spp, jitter, 0xfeedbeefull, frame, x, y);
          sampler.PixelSamples(x, y, got.data());
          PixelSamples(settings, frame, x, y, single.data());
          for (int k = 0; k < spp; ++k) {
            // Bits, not closeness: EXPECT_EQ on doubles.
            EXPECT_EQ(got[k].x(), want[k].x()) << "spp " << spp << " jitter " << jitter << " frame "
                                               << frame << " pixel " << x << "," << y << " k " << k;
            EXPECT_EQ(got[k].y(), want[k].y());
            EXPECT_EQ(single[k], got[k]);
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace lsds
