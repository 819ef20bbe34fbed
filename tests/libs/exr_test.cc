#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "libs/exr/deep_image.h"
#include "libs/exr/exr_info.h"
#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "tests/test_util.h"

namespace lsds::exr {
namespace {

FlatImage MakeFlat(int w, int h) {
  FlatImage image(w, h);
  FlatChannel& id = image.AddChannel("id", PixelType::kUint);
  FlatChannel& z = image.AddChannel("Z", PixelType::kFloat);
  FlatChannel& r = image.AddChannel("R", PixelType::kHalf);
  for (size_t i = 0; i < image.pixel_count(); ++i) {
    id.uints[i] = static_cast<uint32_t>(i * 2654435761u);  // all 32 bits used
    z.floats[i] = 0.1f * static_cast<float>(i) + 1e-7f;
    r.floats[i] = 0.25f * static_cast<float>(i % 7);  // exactly representable in HALF
  }
  z.floats[3] = std::numeric_limits<float>::infinity();
  return image;
}

TEST(FlatExr, RoundTripEveryPixelType) {
  lsds::testing::TempDir dir;
  const FlatImage written = MakeFlat(7, 5);
  WriteOptions options;
  options.compression = Compression::kZip;
  WriteFlatExr(dir / "a.exr", written, options);
  const FlatImage read = ReadFlatExr(dir / "a.exr");
  ASSERT_EQ(read.width(), 7);
  ASSERT_EQ(read.height(), 5);
  EXPECT_EQ(read.Get("id").type, PixelType::kUint);
  EXPECT_EQ(read.Get("id").uints, written.Get("id").uints);
  EXPECT_EQ(read.Get("Z").floats, written.Get("Z").floats);
  EXPECT_EQ(read.Get("R").type, PixelType::kHalf);
  EXPECT_EQ(read.Get("R").floats, written.Get("R").floats);
}

TEST(FlatExr, ReadsOnlyRequestedChannelsAndNamesMissingOnes) {
  lsds::testing::TempDir dir;
  WriteFlatExr(dir / "a.exr", MakeFlat(4, 4));
  const FlatImage read = ReadFlatExr(dir / "a.exr", {"Z"});
  EXPECT_EQ(read.channels().size(), 1u);
  try {
    ReadFlatExr(dir / "a.exr", {"nope"});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.exr"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("nope"), std::string::npos);
  }
}

TEST(FlatExr, HeaderCameraAndInfo) {
  lsds::testing::TempDir dir;
  WriteOptions options;
  HeaderCamera camera;
  camera.cam_from_world << 1, 0, 0, 1, 0, -1, 0, 2, 0, 0, -1, 3, 0, 0, 0, 1;
  camera.ndc_from_world = 2 * camera.cam_from_world;
  options.camera = camera;
  options.compression = Compression::kPiz;
  WriteFlatExr(dir / "a.exr", MakeFlat(3, 2), options);
  const ExrInfo info = ReadExrInfo(dir / "a.exr");
  EXPECT_EQ(info.width, 3);
  EXPECT_EQ(info.height, 2);
  EXPECT_FALSE(info.deep);
  EXPECT_EQ(info.compression, Compression::kPiz);
  ASSERT_TRUE(info.camera);
  EXPECT_TRUE(info.camera->cam_from_world.isApprox(camera.cam_from_world));
  ASSERT_NE(info.Find("id"), nullptr);
  EXPECT_EQ(info.Find("id")->type, PixelType::kUint);
}

TEST(FlatExr, LimitsCheckedBeforeDecoding) {
  lsds::testing::TempDir dir;
  WriteFlatExr(dir / "a.exr", MakeFlat(64, 64));
  ReadLimits limits;
  limits.max_pixels = 100;
  EXPECT_THROW(ReadFlatExr(dir / "a.exr", {}, limits), Error);
  EXPECT_THROW(ReadExrInfo(dir / "a.exr", limits), Error);
}

TEST(FlatExr, TruncatedAndGarbageFilesAreErrorsNotCrashes) {
  lsds::testing::TempDir dir;
  WriteFlatExr(dir / "a.exr", MakeFlat(64, 64));
  const auto size = std::filesystem::file_size(dir / "a.exr");
  std::filesystem::copy_file(dir / "a.exr", dir / "t.exr");
  std::filesystem::resize_file(dir / "t.exr", size / 2);
  EXPECT_THROW(ReadFlatExr(dir / "t.exr"), Error);
  std::ofstream(dir / "g.exr") << "not an exr at all";
  EXPECT_THROW(ReadFlatExr(dir / "g.exr"), Error);
  EXPECT_THROW(ReadExrInfo(dir / "missing.exr"), Error);
}

// The fuzzers' findings: a header that declares more than the file holds is
// refused by the pre-scan, naming the attribute, before OpenEXR allocates it.
TEST(FlatExr, HeaderDeclaringMoreThanTheFileHoldsIsRefusedFirst) {
  lsds::testing::TempDir dir;
  WriteFlatExr(dir / "a.exr", MakeFlat(8, 8));
  std::string bytes;
  {
    std::ifstream in(dir / "a.exr", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  auto patched = [&](const std::string& attribute, size_t skip, const std::string& value) {
    std::string copy = bytes;
    const size_t at = copy.find(attribute);
    EXPECT_NE(at, std::string::npos) << attribute;
    copy.replace(at + attribute.size() + skip, value.size(), value);
    const auto path = dir / ("p" + std::to_string(at) + ".exr");
    std::ofstream(path, std::ios::binary) << copy;
    return path;
  };
  auto message = [](const std::filesystem::path& path) {
    try {
      ReadFlatExr(path);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("read");
  };
  // The size field of "compression" (after its type name) set to 2^31 - 1.
  const std::string huge("\xff\xff\xff\x7f", 4);
  const std::string text = message(patched(std::string("compression\0compression\0", 24), 0, huge));
  EXPECT_NE(text.find("attribute 'compression'"), std::string::npos) << text;
  EXPECT_NE(text.find("malformed EXR header"), std::string::npos) << text;
  // A data window of 2^30 lines in a file of a few hundred bytes.
  const std::string lines("\x00\x00\x00\x40", 4);
  const std::string window =
      message(patched(std::string("dataWindow\0box2i\0", 17), 4 + 12, lines));
  EXPECT_NE(window.find("data window"), std::string::npos) << window;
  EXPECT_THROW(ReadExrInfo(patched(std::string("dataWindow\0box2i\0", 17), 4 + 12, lines)), Error);
}

TEST(FlatExr, WriteIsAtomic) {
  lsds::testing::TempDir dir;
  WriteFlatExr(dir / "a.exr", MakeFlat(4, 4));
  // Only the final file exists: no temporary left behind.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

TEST(DeepExr, RoundTripVariableSampleCounts) {
  lsds::testing::TempDir dir;
  const int w = 5, h = 3;
  std::vector<uint32_t> counts(w * h);
  for (int i = 0; i < w * h; ++i)
    counts[i] = static_cast<uint32_t>(i % 4);  // includes empty pixels
  DeepImage written(w, h, counts);
  DeepChannel& id = written.AddChannel("instanceid", PixelType::kUint);
  DeepChannel& z = written.AddChannel("Z", PixelType::kFloat);
  DeepChannel& s = written.AddChannel("SX", PixelType::kHalf);
  for (uint64_t k = 0; k < written.total_samples(); ++k) {
    id.uints[k] = static_cast<uint32_t>(k + 1);
    z.floats[k] = 1.5f * static_cast<float>(k);
    s.floats[k] = 0.125f * static_cast<float>(k % 8);
  }
  WriteOptions options;
  options.compression = Compression::kZips;
  WriteDeepExr(dir / "d.exr", written, options);
  EXPECT_TRUE(ReadExrInfo(dir / "d.exr").deep);
  const DeepImage read = ReadDeepExr(dir / "d.exr");
  EXPECT_EQ(read.sample_counts(), counts);
  EXPECT_EQ(read.Get("instanceid").uints, id.uints);
  EXPECT_EQ(read.Get("Z").floats, z.floats);
  EXPECT_EQ(read.Get("SX").floats, s.floats);
  EXPECT_EQ(read.FirstSample(2, 1), written.FirstSample(2, 1));
  // A flat reader refuses a deep file with a clear error.
  EXPECT_THROW(ReadFlatExr(dir / "d.exr"), Error);
}

TEST(DeepExr, SampleLimits) {
  lsds::testing::TempDir dir;
  DeepImage written(2, 2, {3, 3, 3, 3});
  written.AddChannel("Z", PixelType::kFloat);
  WriteOptions options;
  options.compression = Compression::kZips;
  WriteDeepExr(dir / "d.exr", written, options);
  options.compression = Compression::kZip;  // not valid for deep data: a clear error
  EXPECT_THROW(WriteDeepExr(dir / "e.exr", written, options), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "e.exr"));
  ReadLimits limits;
  limits.max_samples_per_pixel = 2;
  EXPECT_THROW(ReadDeepExr(dir / "d.exr", {}, limits), Error);
  limits = ReadLimits();
  limits.max_deep_samples = 11;
  EXPECT_THROW(ReadDeepExr(dir / "d.exr", {}, limits), Error);
}

// A deep image written a band of rows at a time is the file WriteDeepExr
// writes for the same samples, byte for byte, whatever the band height (one
// row, a band that does not divide the height, more rows than the image), in
// every pixel type; the band it is handed holds that band's counts and the
// samples come back in place.
TEST(DeepExr, WrittenInBandsIsTheFileWrittenWhole) {
  lsds::testing::TempDir dir;
  const int width = 5, height = 7;
  std::vector<uint32_t> counts(width * height);
  for (size_t p = 0; p < counts.size(); ++p) counts[p] = static_cast<uint32_t>((p * 7) % 4);
  DeepImage whole(width, height, counts);
  DeepChannel& id = whole.AddChannel("instanceid", PixelType::kUint);
  DeepChannel& z = whole.AddChannel("Z", PixelType::kFloat);
  DeepChannel& h = whole.AddChannel("H", PixelType::kHalf);
  for (uint64_t s = 0; s < whole.total_samples(); ++s) {
    id.uints[s] = static_cast<uint32_t>(1000 + s);
    z.floats[s] = 0.5f + static_cast<float>(s);
    h.floats[s] = 0.25f * static_cast<float>(s);
  }
  WriteOptions options;
  options.compression = Compression::kZips;
  options.attributes["note"] = "banded";
  WriteDeepExr(dir / "whole.exr", whole, options);
  const std::vector<ChannelSpec> specs = {
      {"instanceid", PixelType::kUint}, {"Z", PixelType::kFloat}, {"H", PixelType::kHalf}};
  for (int band_rows : {1, 3, 7, 64}) {
    const std::filesystem::path banded = dir / ("banded_" + std::to_string(band_rows) + ".exr");
    WriteDeepExrInBands(
        banded,
        width,
        counts,
        specs,
        [&](int first_row, DeepImage* band) {
          ASSERT_EQ(band->width(), width);
          ASSERT_LE(band->height(), band_rows);
          for (int y = 0; y < band->height(); ++y) {
            for (int x = 0; x < width; ++x) {
              ASSERT_EQ(band->SampleCount(x, y), whole.SampleCount(x, first_row + y));
              const uint64_t from = whole.FirstSample(x, first_row + y),
                             to = band->FirstSample(x, y);
              for (uint32_t k = 0; k < band->SampleCount(x, y); ++k) {
                for (const ChannelSpec& spec : specs) {
                  if (spec.type == PixelType::kUint) {
                    band->Get(spec.name).uints[to + k] = whole.Get(spec.name).uints[from + k];
                  } else {
                    band->Get(spec.name).floats[to + k] = whole.Get(spec.name).floats[from + k];
                  }
                }
              }
            }
          }
        },
        options,
        band_rows);
    EXPECT_EQ(ReadFile(banded), ReadFile(dir / "whole.exr")) << band_rows;
  }
  const DeepImage read = ReadDeepExr(dir / "banded_3.exr");
  EXPECT_EQ(read.sample_counts(), counts);
  EXPECT_EQ(read.Get("instanceid").uints, id.uints);
  EXPECT_EQ(read.Get("Z").floats, z.floats);
  // Bad input is refused before a file appears.
  EXPECT_THROW(WriteDeepExrInBands(
                   dir / "bad.exr", 3, counts, specs, [](int, DeepImage*) {}, options),
               Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.exr"));
}

TEST(FlatImage, AddChannelsZeroFillsReplacesAndKeepsOthers) {
  FlatImage image(64, 33);
  FlatChannel& kept = image.AddChannel("kept", PixelType::kFloat);
  kept.floats.assign(image.pixel_count(), 2.5f);
  FlatChannel& replaced = image.AddChannel("Z", PixelType::kFloat);
  replaced.floats.assign(image.pixel_count(), 9.f);
  image.AddChannels({{"Z", PixelType::kUint}, {"R", PixelType::kHalf}, {"R", PixelType::kHalf}});
  ASSERT_EQ(image.channels().size(), 3u);
  EXPECT_EQ(image.Get("kept").floats, std::vector<float>(image.pixel_count(), 2.5f));
  EXPECT_EQ(image.Get("Z").type, PixelType::kUint);
  EXPECT_TRUE(image.Get("Z").floats.empty());
  EXPECT_EQ(image.Get("Z").uints, std::vector<uint32_t>(image.pixel_count(), 0u));
  EXPECT_EQ(image.Get("R").floats, std::vector<float>(image.pixel_count(), 0.f));
}

TEST(DeepImage, AddChannelsEqualsAddChannelOneByOne) {
  std::vector<uint32_t> counts(40 * 17);
  for (size_t i = 0; i < counts.size(); ++i) counts[i] = static_cast<uint32_t>(i % 5);
  DeepImage one_by_one(40, 17, counts), together(40, 17, counts);
  const std::vector<ChannelSpec> specs = {
      {"id", PixelType::kUint}, {"Z", PixelType::kFloat}, {"NX", PixelType::kHalf}};
  for (const ChannelSpec& spec : specs) one_by_one.AddChannel(spec.name, spec.type);
  together.AddChannels(specs);
  ASSERT_EQ(together.channels().size(), specs.size());
  for (size_t c = 0; c < specs.size(); ++c) {
    const DeepChannel& a = one_by_one.channels()[c];
    const DeepChannel& b = together.channels()[c];
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.type, a.type);
    EXPECT_EQ(b.floats, a.floats);
    EXPECT_EQ(b.uints, a.uints);
    EXPECT_EQ(std::max(b.floats.size(), b.uints.size()), together.total_samples());
  }
}

}  // namespace
}  // namespace lsds::exr
