// The page's building blocks: the SVG bars say what the histogram holds, and
// the embedded images decode to what was encoded.
#include <regex>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "report/histogram.h"
#include "report/html.h"
#include "report/svg_plot.h"

namespace lsds::report {
namespace {

TEST(Page, Base64MatchesRfc4648Vectors) {
  EXPECT_EQ(Base64(""), "");
  EXPECT_EQ(Base64("f"), "Zg==");
  EXPECT_EQ(Base64("fo"), "Zm8=");
  EXPECT_EQ(Base64("foo"), "Zm9v");
  EXPECT_EQ(Base64("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64("foobar"), "Zm9vYmFy");
}

// Inverse of Base64, here only to read the data URI back.
std::string Unbase64(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<uint32_t>(alphabet.find(c));
    if ((count += 6) >= 8) {
      count -= 8;
      out += static_cast<char>((bits >> count) & 255);
    }
  }
  return out;
}

TEST(Page, PngDataUriDecodesToTheSamePixels) {
  cv::Mat image(7, 5, CV_8UC3);
  cv::randu(image, 0, 255);
  const std::string uri = ImageDataUri(image, false);
  const std::string prefix = "data:image/png;base64,";
  ASSERT_EQ(uri.rfind(prefix, 0), 0u);
  const std::string bytes = Unbase64(uri.substr(prefix.size()));
  const cv::Mat decoded =
      cv::imdecode(std::vector<uchar>(bytes.begin(), bytes.end()), cv::IMREAD_COLOR);
  ASSERT_EQ(decoded.size(), image.size());
  EXPECT_EQ(cv::norm(decoded, image, cv::NORM_INF), 0);
}

TEST(Page, SvgBarsCarryTheHistogramCounts) {
  Histogram h =
      MakeNumeric("size", "Size", "longer side", "px", "objects", GeometricEdges(1, 64, 2));
  h.warn_below = 8;
  for (double v : {3.0, 3.5, 5.0, 20.0, 20.0, 20.0, 0.5, 100.0, 200.0}) h.Add(v);
  const std::string svg = HistogramSvg(h).str();
  // One tooltip per bar: "[a, b) px: n", plus "<" and ">" bars.
  std::map<std::string, std::string> bars;
  const std::regex tooltip(R"(<title>([^<]*): (\d+)</title>)");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tooltip);
       it != std::sregex_iterator();
       ++it) {
    bars[(*it)[1]] = (*it)[2];
  }
  EXPECT_EQ(bars.at("[2, 4) px"), "2");
  EXPECT_EQ(bars.at("[4, 8) px"), "1");
  EXPECT_EQ(bars.at("[16, 32) px"), "3");
  EXPECT_EQ(bars.at("&lt; 1 px"), "1");
  EXPECT_EQ(bars.at("&gt; 64 px"), "2");
  int64_t total = 0;
  for (const auto& [range, count] : bars) total += std::stoll(count);
  EXPECT_EQ(total, h.total());
  // Shown: "<", [2, 4) (the first non-empty bin) to [32, 64] (five bins at
  // least), ">". Those under 8 px and the outliers are warnings: "<", [2, 4),
  // [4, 8), ">".
  size_t warn = 0;
  for (size_t at = svg.find("bar warn"); at != std::string::npos; at = svg.find("bar warn", at + 1))
    ++warn;
  EXPECT_EQ(warn, 4u);
  EXPECT_EQ(bars.count("[1, 2) px"), 0u);
  EXPECT_EQ(bars.at("[32, 64] px"), "0");
  EXPECT_NE(svg.find("longer side (px)"), std::string::npos);
}

}  // namespace
}  // namespace lsds::report
