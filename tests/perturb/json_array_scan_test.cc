// The streaming array scan: elements and raw bytes exactly as in the file,
// whatever the strings hold and wherever the 1 MiB read chunks cut.
#include <gtest/gtest.h>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "perturb/json_array_scan.h"
#include "tests/perturb/perturb_test_util.h"

namespace lsds::noise {
namespace {

using testing_perturb::TempDir;

TEST(JsonArrayScan, HandsOutElementsRawBytesAndTheHeader) {
  TempDir dir;
  const auto path = dir.path() / "a.json";
  const std::string frames =
      "\n  {\"s\": \"a],[\\\"}{\", \"v\": [1, [2, 3]]} ,\n  7,\"x\\\\\" , [], "
      "{\"frames\": [9]}\n";
  WriteFileAtomic(
      path, "{\"before\": {\"frames\": 1}, \"frames\": [" + frames + "], \"after\": [\"]\"]}\n");
  std::vector<std::string> elements;
  std::string raw;
  const ArrayScanResult result = ScanJsonArrayMember(path,
                                                     "frames",
                                                     {[&](std::string_view bytes) { raw += bytes; },
                                                      [&](std::string_view text, size_t index) {
                                                        EXPECT_EQ(index, elements.size());
                                                        elements.emplace_back(text);
                                                      }});
  EXPECT_TRUE(result.found);
  EXPECT_EQ(result.elements, 5u);
  EXPECT_EQ(raw, frames);
  ASSERT_EQ(elements.size(), 5u);
  EXPECT_EQ(elements[0], "{\"s\": \"a],[\\\"}{\", \"v\": [1, [2, 3]]}");
  EXPECT_EQ(elements[1], "7");
  EXPECT_EQ(elements[2], "\"x\\\\\"");
  EXPECT_EQ(elements[3], "[]");
  EXPECT_EQ(elements[4], "{\"frames\": [9]}");
  EXPECT_EQ(result.header,
            nlohmann::json::parse(R"({"before": {"frames": 1}, "frames": [], "after": ["]"]})"));
}

TEST(JsonArrayScan, ElementsCrossingReadChunksAreWhole) {
  TempDir dir;
  const auto path = dir.path() / "big.json";
  nlohmann::json header = {{"format", "x"}};
  std::string text = ArrayFileHead(header, "frames");
  std::string frames;
  const int count = 3000;  // ~1.5 MB: several chunk boundaries
  for (int k = 0; k < count; ++k) {
    frames += (k == 0 ? "\n    " : ",\n    ") +
              nlohmann::json({{"index", k}, {"pad", std::string(500, 'a' + k % 26)}}).dump();
  }
  WriteFileAtomic(path, text + frames + "\n  ]\n}\n");
  int seen = 0;
  std::string raw;
  ScanJsonArrayMember(path,
                      "frames",
                      {[&](std::string_view bytes) { raw += bytes; },
                       [&](std::string_view element, size_t index) {
                         const nlohmann::json json = ParseElement(element, path, "/frames");
                         EXPECT_EQ(json["index"].get<int>(), static_cast<int>(index));
                         EXPECT_EQ(json["pad"].get<std::string>().size(), 500u);
                         ++seen;
                       }});
  EXPECT_EQ(seen, count);
  EXPECT_EQ(raw, frames + "\n  ");
}

TEST(JsonArrayScan, BadJsonIsAnErrorNamingTheFile) {
  TempDir dir;
  const auto path = dir.path() / "bad.json";
  WriteFileAtomic(path, "{\"frames\": [1, 2");
  EXPECT_THROW(ScanJsonArrayMember(path, "frames"), Error);
  WriteFileAtomic(path, "[1, 2]");
  EXPECT_THROW(ScanJsonArrayMember(path, "frames"), Error);
  WriteFileAtomic(path, "{\"a\": }");
  EXPECT_THROW(ScanJsonArrayMember(path, "frames"), Error);
  try {
    ParseElement("{\"a\": ", path, "/frames/3");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("#/frames/3"), std::string::npos) << e.what();
  }
}

// A file cut between two elements: the message names the end of the file,
// where the closing ']' was expected.
TEST(JsonArrayScan, AnArrayCutBetweenElementsNamesTheEndOfTheFile) {
  TempDir dir;
  const auto path = dir.path() / "cut.json";
  WriteFileAtomic(path, "{\"frames\": [\n  {\"index\": 0},\n  {\"index\": 1},\n");
  try {
    ScanJsonArrayMember(path, "frames");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cut.json:4:1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lsds::noise
