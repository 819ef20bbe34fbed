// The .npy header: the byte layout numpy.lib.format specifies.
#include <gtest/gtest.h>

#include "libs/export/npy.h"

namespace lsds::layer_export {
namespace {

TEST(NpyHeader, AlignsDataTo64BytesAndSpellsShapesAsPythonTuples) {
  for (const std::vector<int64_t>& shape :
       std::vector<std::vector<int64_t>>{{48, 64}, {48, 64, 3}, {7}}) {
    const std::string header = NpyHeader("<f4", shape);
    EXPECT_EQ(header.size() % 64, 0u);
    EXPECT_EQ(header.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    const size_t length = static_cast<unsigned char>(header[8]) |
                          (static_cast<unsigned char>(header[9]) << 8);
    EXPECT_EQ(length + 10, header.size());
    EXPECT_EQ(header.back(), '\n');
  }
  EXPECT_NE(NpyHeader("<u4", {48, 64}).find("'shape': (48, 64), }"),
            std::string::npos);
  EXPECT_NE(NpyHeader("<u4", {7}).find("'shape': (7,), }"), std::string::npos);
  EXPECT_NE(NpyHeader("<f4", {2, 3, 3}).find("'descr': '<f4'"),
            std::string::npos);
}

}  // namespace
}  // namespace lsds::layer_export
