// libs/util/npy.h: .npy files as numpy.save writes them (byte-exact headers
// below), plain and structured, versions 1 and 2, and located errors for what
// is not supported.
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "libs/util/error.h"
#include "libs/util/npy.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;

std::string Bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

template <typename T>
void Put(std::string* out, T v) {
  char raw[sizeof v];
  std::memcpy(raw, &v, sizeof v);
  out->append(raw, sizeof v);
}

TEST(Npy, WritesNumpysVersion1HeaderAndReadsItBack) {
  TempDir dir;
  std::string data;
  for (float v : {1.5f, -2.0f, 3.25f, 0.0f, 5.0f, 6.0f}) Put(&data, v);
  WriteNpy(dir / "a.npy", "'<f4'", {2, 3}, data);
  const std::string bytes = Bytes(dir / "a.npy");
  // numpy.save(np.zeros((2, 3), np.float32)): magic, 1.0, header length 118,
  // the dict padded with spaces to 128 bytes in all, ending in '\n'.
  const std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
  ASSERT_EQ(bytes.size(), 128u + data.size());
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  EXPECT_EQ(static_cast<unsigned char>(bytes[8]), 118);
  EXPECT_EQ(bytes.substr(10, dict.size()), dict);
  EXPECT_EQ(bytes[127], '\n');
  const NpyArray array = ReadNpy(dir / "a.npy");
  EXPECT_EQ(array.shape, (std::vector<int64_t>{2, 3}));
  EXPECT_EQ(array.Get(2, array.fields[0]), 3.25);
  EXPECT_EQ(array.Get(5, array.fields[0]), 6.0);
}

TEST(Npy, ReadsStructuredRecordsWithSubArraysByName) {
  TempDir dir;
  std::string data;
  for (uint32_t id : {7u, 9u}) {
    Put(&data, id);
    for (int e = 0; e < 16; ++e) Put(&data, static_cast<float>(id * 100 + e));
    Put(&data, 0.25);  // '<f8'
  }
  WriteNpy(dir / "r.npy",
           "[('semanticId', '<u4'), ('transform', '<f4', (4, 4)), "
           "('occlusionRatio', '<f8')]",
           {2},
           data);
  // A one-element tuple as Python spells it.
  EXPECT_NE(Bytes(dir / "r.npy").find("'shape': (2,), }"), std::string::npos);
  const NpyArray array = ReadNpy(dir / "r.npy");
  ASSERT_EQ(array.size(), 2);
  EXPECT_EQ(array.record_size, 4u + 64u + 8u);
  const NpyField& transform = array.Field("transform", "r.npy");
  EXPECT_EQ(transform.count, 16);
  EXPECT_EQ(array.Get(1, array.Field("semanticId", "r.npy")), 9);
  EXPECT_EQ(array.Get(1, transform, 13), 913);
  EXPECT_EQ(array.Get(0, array.Field("occlusionRatio", "r.npy")), 0.25);
  EXPECT_THROW(array.Field("corners", "r.npy"), Error);
}

TEST(Npy, ReadsVersion2Headers) {
  TempDir dir;
  std::string header = "{'descr': '<u2', 'fortran_order': False, 'shape': (3,), }";
  header.append((64 - (12 + header.size() + 1) % 64) % 64, ' ');
  header += '\n';
  std::string bytes = std::string("\x93NUMPY\x02\x00", 8);
  Put(&bytes, static_cast<uint32_t>(header.size()));
  bytes += header;
  for (uint16_t v : {1, 2, 65535}) Put(&bytes, v);
  std::ofstream(dir / "v2.npy", std::ios::binary) << bytes;
  const NpyArray array = ReadNpy(dir / "v2.npy");
  EXPECT_EQ(array.shape, (std::vector<int64_t>{3}));
  EXPECT_EQ(array.Get(2, array.fields[0]), 65535);
}

TEST(Npy, UnsupportedOrBrokenFilesAreLocatedErrors) {
  TempDir dir;
  auto message = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    try {
      ReadNpy(dir / name);
    } catch (const Error& e) {
      EXPECT_NE(e.location().file.find(name), std::string::npos);
      return e.message();
    }
    return std::string("no error");
  };
  EXPECT_NE(message("magic.npy", "PK\x03\x04 not numpy").find("magic"), std::string::npos);
  std::string data(8, '\0');
  WriteNpy(dir / "big.npy", "'>f8'", {1}, data);
  EXPECT_NE(message("big2.npy", Bytes(dir / "big.npy")).find("unsupported dtype"),
            std::string::npos);
  WriteNpy(dir / "short.npy", "'<f8'", {2}, data);  // 8 of 16 bytes
  EXPECT_NE(message("short2.npy", Bytes(dir / "short.npy")).find("header says 16"),
            std::string::npos);
  std::string fortran = Bytes(dir / "short.npy");
  const size_t at = fortran.find("False");
  fortran.replace(at, 5, "True ");
  EXPECT_NE(message("fortran.npy", fortran).find("Fortran"), std::string::npos);
}

}  // namespace
}  // namespace lsds::testing
