// The decoders' limits on tiny crafted files whose headers lie: every one is
// refused with an lsds::Error naming the file (and the place) before anything
// of the declared size is allocated, which the peak resident memory of this
// process shows (getrusage), and nested or sparse inputs finish at once.
#include <sys/resource.h>

#include <chrono>
#include <cstdint>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "importers/indexed_png.h"
#include "importers/pfm.h"
#include "importers/source_exr.h"
#include "importers/source_png.h"
#include "libs/collection/json_stream.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "libs/util/limits.h"
#include "libs/util/npy.h"
#include "perturb/json_array_scan.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;

constexpr uint64_t kGiB = uint64_t{1} << 30;

// Under AddressSanitizer (make test-asan) the shadow of a large reservation is resident, an eighth
// of it, whether or not the buffer is touched: the resident-memory bounds are checked by the
// release suite only.
#if defined(__SANITIZE_ADDRESS__)  // gcc
#define LSDS_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)  // clang (the sanitizer preset)
#define LSDS_UNDER_ASAN 1
#endif
#endif
#if defined(LSDS_UNDER_ASAN)
constexpr bool kResidentMemoryMeasured = false;
#else
constexpr bool kResidentMemoryMeasured = true;
#endif

// Peak resident memory of this process so far, bytes.
int64_t PeakRss() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<int64_t>(usage.ru_maxrss) * 1024;
}

// Runs `read`, which must throw lsds::Error, and returns it; fails the test
// when the peak memory grows by more than 64 MiB on the way (every bomb here
// declares gigabytes).
template <typename Read>
Error Refusal(Read&& read) {
  const int64_t before = PeakRss();
  try {
    read();
  } catch (const Error& e) {
    if (kResidentMemoryMeasured) {
      EXPECT_LT(PeakRss() - before, int64_t{64} << 20) << e.what();
    }
    return e;
  }
  ADD_FAILURE() << "no error";
  return Error("no error");
}

void Write(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

void Sparse(const fs::path& path, uint64_t size) {
  std::ofstream(path, std::ios::binary).close();
  fs::resize_file(path, size);
}

std::string Be32(uint32_t v) {
  return {static_cast<char>(v >> 24),
          static_cast<char>(v >> 16),
          static_cast<char>(v >> 8),
          static_cast<char>(v)};
}

// PNG's CRC-32 (bitwise; the files are tiny).
uint32_t Crc32(const std::string& bytes) {
  uint32_t crc = 0xffffffffu;
  for (const char c : bytes) {
    crc ^= static_cast<unsigned char>(c);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

std::string Chunk(const std::string& kind, const std::string& data) {
  const std::string body = kind + data;
  return Be32(static_cast<uint32_t>(data.size())) + body + Be32(Crc32(body));
}

// A PNG whose IHDR declares width x height, with a tiny IDAT.
std::string Png(uint32_t width, uint32_t height, int colour_type) {
  std::string ihdr = Be32(width) + Be32(height);
  ihdr += static_cast<char>(8);
  ihdr += static_cast<char>(colour_type);
  ihdr += std::string(3, '\0');
  std::string out = "\x89PNG\r\n\x1a\n" + Chunk("IHDR", ihdr);
  if (colour_type == 3) out += Chunk("PLTE", std::string(6, '\0'));
  // A zlib stream of a few zero bytes (stored block).
  out += Chunk("IDAT", std::string("\x78\x01\x01\x04\x00\xfb\xff\0\0\0\0\0\x04\0\x01", 15));
  return out + Chunk("IEND", "");
}

TEST(DecoderLimits, PngHeaderOfAMillionSquaredIsRefusedUndecoded) {
  testing::TempDir dir;
  const fs::path path = dir / "huge.png";
  Write(path, Png(1000000, 1000000, 2));
  Error e = Refusal([&] { import::ReadImage(path, -1); });
  EXPECT_EQ(e.location().file, path.string());
  EXPECT_NE(e.message().find("declares 1000000x1000000"), std::string::npos) << e.what();
  // Where the size is known, the header is compared with it first.
  e = Refusal([&] { import::ReadSrgbLayer(path, 64, 48, "the test"); });
  EXPECT_NE(e.message().find("declares 1000000x1000000, expected a 64x48"), std::string::npos)
      << e.what();
  e = Refusal([&] { import::ReadRgbaPng(path, 64, 48); });
  EXPECT_EQ(e.location().file, path.string());
  // Within the side limit but more pixels than 100 bytes can inflate to.
  Write(path, Png(16000, 16000, 0));
  e = Refusal([&] { import::ReadImage(path, 0); });
  EXPECT_NE(e.message().find("more than a file of"), std::string::npos) << e.what();
}

TEST(DecoderLimits, PalettePngBombIsRefusedBeforeLibpngAllocates) {
  testing::TempDir dir;
  const fs::path path = dir / "seg.png";
  Write(path, Png(16000, 16000, 3));
  EXPECT_LT(fs::file_size(path), 120u);
  const Error e = Refusal([&] { import::ReadIndexedPng(path); });
  EXPECT_EQ(e.location().file, path.string());
  EXPECT_NE(e.message().find("16000x16000"), std::string::npos) << e.what();
  EXPECT_NE(e.message().find("more than a file of"), std::string::npos) << e.what();
}

TEST(DecoderLimits, PngOverTheMemoryBudgetNamesTheBudget) {
  testing::TempDir dir;
  const fs::path path = dir / "a.png";
  // 4000 x 4000 grey decodes to 16 MB: legal for its file size (2 MB of
  // compressed zeros would hold it), over a 1 MiB budget.
  Write(path, Png(4000, 4000, 0) + std::string(size_t{1} << 14, '\0'));
  SetMemoryBudget("1M");
  const Error e = Refusal([&] { import::ReadImage(path, 0); });
  SetMemoryBudget("8G");
  EXPECT_NE(e.message().find("over the memory budget"), std::string::npos) << e.what();
}

TEST(DecoderLimits, PfmHeaderIsCheckedAgainstTheFileBeforeAllocating) {
  testing::TempDir dir;
  const fs::path path = dir / "d.pfm";
  Write(path, "PF\n32768 32768\n-1\n");  // 18 bytes declaring 12 GiB
  Error e = Refusal([&] { import::ReadPfm(path, import::PfmRows::kTopFirst); });
  EXPECT_EQ(e.location().file, path.string());
  EXPECT_NE(e.message().find("shorter than its header says"), std::string::npos) << e.what();
  // Numbers are range-checked where they stand (line 2, column 7).
  Write(path, "Pf\n2 99999999999999999999\n-1\n" + std::string(16, '\0'));
  e = Refusal([&] { import::ReadPfm(path, import::PfmRows::kTopFirst); });
  EXPECT_EQ(e.location().line, 2);
  EXPECT_EQ(e.location().column, 3);
  EXPECT_NE(e.message().find("height"), std::string::npos) << e.what();
  Write(path, "Pf\n2 1\nnan\n" + std::string(8, '\0'));
  e = Refusal([&] { import::ReadPfm(path, import::PfmRows::kTopFirst); });
  EXPECT_NE(e.message().find("scale"), std::string::npos) << e.what();
  // A sparse gigabyte: the header is read from its first bytes only.
  Sparse(path, kGiB);
  e = Refusal([&] { import::ReadPfm(path, import::PfmRows::kTopFirst); });
  EXPECT_NE(e.message().find("not a PFM file"), std::string::npos) << e.what();
  // And a good one still reads, bottom row first by the specification.
  import::PfmImage image;
  image.width = 2, image.height = 3;
  image.values = {1, 2, 3, 4, 5, 6};
  import::WritePfm(path, image, import::PfmRows::kBottomFirst);
  EXPECT_EQ(import::ReadPfm(path, import::PfmRows::kBottomFirst).values, image.values);
  EXPECT_EQ(import::ReadPfm(path, import::PfmRows::kTopFirst).values,
            (std::vector<float>{5, 6, 3, 4, 1, 2}));
}

TEST(DecoderLimits, ExrAttributeBombThroughTheImportReader) {
  testing::TempDir dir;
  const fs::path path = dir / "shot.0000.exr";
  std::string bytes("\x76\x2f\x31\x01\x02\0\0\0", 8);
  bytes += std::string("comments\0string\0", 16);
  bytes += std::string("\x00\x00\xf0\x7f", 4);  // 2 GB declared
  bytes += std::string(64, 'x');
  Write(path, bytes);
  const Error e = Refusal([&] { import::SourceExr exr(path); });
  EXPECT_EQ(e.location().file, path.string());
  EXPECT_NE(e.message().find("attribute 'comments'"), std::string::npos) << e.what();
}

std::string NpyV2(const std::string& header) {
  const std::string text = header + "\n";
  std::string out("\x93NUMPY\x02\x00", 8);
  const auto n = static_cast<uint32_t>(text.size());
  out += std::string{static_cast<char>(n),
                     static_cast<char>(n >> 8),
                     static_cast<char>(n >> 16),
                     static_cast<char>(n >> 24)};
  return out + text;
}

TEST(DecoderLimits, NpyNestedHeadersAreBoundedAndFast) {
  testing::TempDir dir;
  const fs::path path = dir / "a.npy";
  const int deep = 100000;
  std::string nested;
  for (int k = 0; k < deep; ++k) nested += '(';
  nested += '1';
  for (int k = 0; k < deep; ++k) nested += ",)";
  const auto start = std::chrono::steady_clock::now();
  Write(path, NpyV2("{'descr': '<f4', 'fortran_order': False, 'shape': " + nested + ", }"));
  Error e = Refusal([&] { ReadNpy(path); });
  EXPECT_NE(e.message().find("nesting deeper than 256"), std::string::npos) << e.what();
  Write(path,
        NpyV2("{'descr': [('x', '<f4', " + nested + ")], 'fortran_order': False, " +
              "'shape': (1,), }"));
  e = Refusal([&] { ReadNpy(path); });
  EXPECT_NE(e.message().find("nesting deeper than 256"), std::string::npos) << e.what();
  // 200,000 numbers in one flat tuple: linear, not quadratic (each number
  // was read from a copy of the rest of the header).
  std::string wide = "(";
  for (int k = 0; k < 200000; ++k) wide += "1, ";
  Write(path, NpyV2("{'descr': '<f4', 'fortran_order': False, 'shape': " + wide + "), }"));
  e = Refusal([&] { ReadNpy(path); });
  EXPECT_NE(e.message().find("its header says 4"), std::string::npos) << e.what();
  // Headers beyond 1 MiB are refused unparsed.
  Write(path,
        NpyV2("{'descr': '<f4', 'fortran_order': False, 'shape': (" +
              std::string(size_t{2} << 20, ' ') + "1,), }"));
  e = Refusal([&] { ReadNpy(path); });
  EXPECT_NE(e.message().find("over lsds's limit"), std::string::npos) << e.what();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
}

TEST(DecoderLimits, NpyShapesAreRangeChecked) {
  testing::TempDir dir;
  const fs::path path = dir / "a.npy";
  // 2^32 x 2^32 wraps to 0 in 64 bits: an empty payload would "match".
  Write(path,
        NpyV2("{'descr': '<f4', 'fortran_order': False, 'shape': (4294967296, "
              "4294967296), }"));
  Error e = Refusal([&] { ReadNpy(path); });
  EXPECT_NE(e.message().find("overflows"), std::string::npos) << e.what();
  Write(path,
        NpyV2("{'descr': '<f4', 'fortran_order': False, 'shape': (99999999999999999999,), }"));
  e = Refusal([&] { ReadNpy(path); });
  EXPECT_NE(e.message().find("int64"), std::string::npos) << e.what();
  Write(path, NpyV2("{'descr': [('x', '<f4', ((2,),))], 'fortran_order': False, 'shape': (1,), }"));
  e = Refusal([&] { ReadNpy(path); });
  EXPECT_NE(e.message().find("shape of field 'x'"), std::string::npos) << e.what();
  // The payload is checked against the file before it is allocated.
  Write(path, NpyV2("{'descr': '<f8', 'fortran_order': False, 'shape': (100000000,), }"));
  e = Refusal([&] { ReadNpy(path); });
  EXPECT_NE(e.message().find("header says 800000000"), std::string::npos) << e.what();
  Sparse(path, kGiB);
  e = Refusal([&] { ReadNpy(path); });
  EXPECT_NE(e.message().find("magic"), std::string::npos) << e.what();
}

TEST(DecoderLimits, ReadFileChecksTheBudgetAndReadsOnce) {
  testing::TempDir dir;
  const fs::path path = dir / "sparse.bin";
  Sparse(path, kGiB);
  SetMemoryBudget("256M");
  Error e = Refusal([&] { ReadFile(path); });
  SetMemoryBudget("8G");
  EXPECT_NE(e.message().find("over the memory budget"), std::string::npos) << e.what();
  // A text reader stops at the first chunk: a NUL at 1:1.
  e = Refusal([&] { ReadTextFile(path); });
  EXPECT_EQ(e.location().line, 1);
  EXPECT_EQ(e.location().column, 1);
  // Bytes come back as they are, across chunk boundaries.
  std::string bytes(3 * (size_t{1} << 20) + 17, '\0');
  for (size_t k = 0; k < bytes.size(); ++k) bytes[k] = static_cast<char>(k * 7 + k / 4096);
  Write(dir / "b.bin", bytes);
  EXPECT_EQ(ReadFile(dir / "b.bin"), bytes);
  // 64 MiB of zeros read whole: one buffer, not a stream's copy and a string.
  Sparse(dir / "z.bin", uint64_t{64} << 20);
  const int64_t before = PeakRss();
  EXPECT_EQ(ReadFile(dir / "z.bin").size(), size_t{64} << 20);
  if (kResidentMemoryMeasured) {
    EXPECT_LT(PeakRss() - before, int64_t{100} << 20);
  }
}

TEST(DecoderLimits, NulBytesInJsonAreErrorsWhereTheyAre) {
  testing::TempDir dir;
  // nlohmann alone takes the NUL for the end and parses {"a": 1}.
  const std::string text("{\"a\": 1}\n\0{\"b\": 2}", 18);
  Error e = Refusal([&] { ParseJsonText(text, "t.json"); });
  EXPECT_EQ(e.location().line, 2);
  EXPECT_EQ(e.location().column, 1);
  EXPECT_NE(e.message().find("NUL"), std::string::npos) << e.what();

  Write(dir / "c.json", text);
  e = Refusal([&] { ReadJsonFile(dir / "c.json"); });
  EXPECT_EQ(e.location().line, 2);
  // The streaming reader of collection.json and metadata.json, after the
  // document and inside it.
  Write(dir / "s.json", std::string("{\"frames\": [1, 2]}\n\n  \0junk", 27));
  e = Refusal([&] { StreamJsonArrayMember(dir / "s.json", "frames", nullptr, nullptr); });
  EXPECT_EQ(e.location().file, (dir / "s.json").string());
  EXPECT_EQ(e.location().line, 3);
  EXPECT_EQ(e.location().column, 3);
  Write(dir / "s.json", std::string("{\"frames\": [1,\n \0 2]}", 21));
  e = Refusal([&] { StreamJsonArrayMember(dir / "s.json", "frames", nullptr, nullptr); });
  EXPECT_EQ(e.location().line, 2);
  EXPECT_EQ(e.location().column, 2);
  // perturb-metadata's scanner.
  e = Refusal([&] { noise::ScanJsonArrayMember(dir / "s.json", "frames", {}); });
  EXPECT_EQ(e.location().line, 2);
  EXPECT_EQ(e.location().column, 2);
  // A sparse gigabyte is refused at its first byte, without reading the rest.
  Sparse(dir / "big.json", kGiB);
  const auto start = std::chrono::steady_clock::now();
  e = Refusal([&] { StreamJsonArrayMember(dir / "big.json", "frames", nullptr, nullptr); });
  EXPECT_EQ(e.location().line, 1);
  EXPECT_EQ(e.location().column, 1);
  e = Refusal([&] { ReadJsonFile(dir / "big.json"); });
  EXPECT_EQ(e.location().column, 1);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  // Without a NUL the streaming reader still reads the whole document.
  Write(dir / "ok.json", "{\"frames\": [1, 2, 3], \"x\": 4}");
  nlohmann::json header;
  EXPECT_EQ(StreamJsonArrayMember(dir / "ok.json", "frames", &header, nullptr), 3u);
  EXPECT_EQ(header.at("x"), 4);
}

}  // namespace
}  // namespace lsds
