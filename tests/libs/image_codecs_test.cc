// The image codecs behind the plug-in (libs/imaging/image_codecs.h) against OpenCV's imgcodecs
// called directly, and the plug-in loader's errors (libs/util/plugin.h).
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "libs/imaging/image_codecs.h"
#include "libs/imaging/image_codecs_abi.h"
#include "libs/util/error.h"
#include "libs/util/plugin.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

// A deterministic picture with every channel varying, so that a codec difference shows.
cv::Mat TestImage(int type) {
  cv::Mat image(13, 17, type);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      for (int c = 0; c < image.channels(); ++c) {
        const int value = (37 * x + 11 * y + 71 * c) % 251;
        if (image.depth() == CV_16U)
          image.ptr<uint16_t>(y)[x * image.channels() + c] = static_cast<uint16_t>(value * 257);
        else
          image.ptr<uint8_t>(y)[x * image.channels() + c] = static_cast<uint8_t>(value);
      }
  return image;
}

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// LSDS_PLUGIN_DIR set for the life of the object. The tests of this binary run on one thread.
class ScopedPluginDir {
 public:
  explicit ScopedPluginDir(const std::string& dir) {
    setenv("LSDS_PLUGIN_DIR", dir.c_str(), 1);  // NOLINT(concurrency-mt-unsafe): one thread
  }
  ~ScopedPluginDir() { unsetenv("LSDS_PLUGIN_DIR"); }  // NOLINT(concurrency-mt-unsafe)
  ScopedPluginDir(const ScopedPluginDir&) = delete;
  ScopedPluginDir& operator=(const ScopedPluginDir&) = delete;
};

bool SameMat(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(ImageCodecs, EncodeAndDecodeGiveOpenCvsBytes) {
  const struct {
    const char* ext;
    int type;
    std::vector<int> params;
  } cases[] = {{".png", CV_8UC3, {cv::IMWRITE_PNG_COMPRESSION, 6}},
               {".png", CV_16UC1, {}},
               {".jpg", CV_8UC3, {cv::IMWRITE_JPEG_QUALITY, 75}},
               {".tiff", CV_8UC4, {}}};
  for (const auto& c : cases) {
    const cv::Mat image = TestImage(c.type);
    std::vector<uchar> ours, reference;
    ASSERT_TRUE(imaging::ImEncode(c.ext, image, ours, c.params)) << c.ext;
    ASSERT_TRUE(cv::imencode(c.ext, image, reference, c.params)) << c.ext;
    EXPECT_EQ(ours, reference) << c.ext;
    for (const int flags : {cv::IMREAD_UNCHANGED, cv::IMREAD_COLOR, cv::IMREAD_GRAYSCALE}) {
      EXPECT_TRUE(SameMat(imaging::ImDecode(ours, flags), cv::imdecode(reference, flags)))
          << c.ext << " flags " << flags;
    }
  }
}

TEST(ImageCodecs, WriteAndReadGiveOpenCvsFiles) {
  testing::TempDir dir;
  const cv::Mat image = TestImage(CV_8UC3);
  const std::string ours = (dir / "ours.png").string(), reference = (dir / "ref.png").string();
  ASSERT_TRUE(imaging::ImWrite(ours, image, {cv::IMWRITE_PNG_COMPRESSION, 9}));
  ASSERT_TRUE(cv::imwrite(reference, image, {cv::IMWRITE_PNG_COMPRESSION, 9}));
  EXPECT_EQ(FileBytes(ours), FileBytes(reference));
  EXPECT_TRUE(SameMat(imaging::ImRead(ours, cv::IMREAD_UNCHANGED),
                      cv::imread(reference, cv::IMREAD_UNCHANGED)));
  // A missing file: an empty image, as from cv::imread.
  EXPECT_TRUE(imaging::ImRead((dir / "missing.png").string(), cv::IMREAD_UNCHANGED).empty());
}

TEST(ImageCodecs, OpenCvExceptionsCrossThePlugIn) {
  const cv::Mat image = TestImage(CV_8UC3);
  std::vector<uchar> bytes;
  // Whatever OpenCV does with an extension it has no encoder for, the plug-in does the same.
  bool reference_threw = false, ours_threw = false;
  try {
    cv::imencode(".no-such-format", image, bytes);
  } catch (const cv::Exception&) {
    reference_threw = true;
  }
  try {
    imaging::ImEncode(".no-such-format", image, bytes);
  } catch (const cv::Exception&) {
    ours_threw = true;
  }
  EXPECT_TRUE(reference_threw);
  EXPECT_EQ(ours_threw, reference_threw);
}

TEST(Plugin, SearchOrderIsEnvironmentThenBesideTheBinaryThenTheBuildTree) {
  std::vector<std::string> dirs;
  {
    const ScopedPluginDir plugin_dir("/nonexistent/plugins");
    dirs = PluginSearchDirs();
  }
  ASSERT_EQ(dirs.size(), 3u);
  EXPECT_EQ(dirs[0], "/nonexistent/plugins");
  // This test binary lives in <build>/tests/libs: beside it is <build>/tests/lib/lsds.
  EXPECT_EQ(dirs[1], testing::BinaryDir() + "/tests/lib/lsds");
  EXPECT_EQ(dirs[2], testing::BinaryDir() + "/lib/lsds");
  EXPECT_EQ(PluginSearchDirs().size(), 2u);
}

TEST(Plugin, AMissingPlugInNamesEveryPathTried) {
  try {
    LoadPluginSymbol("lsds_no_such_plugin.so", "entry");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    for (const std::string& dir : PluginSearchDirs())
      EXPECT_NE(message.find(dir + "/lsds_no_such_plugin.so: not found"), std::string::npos)
          << message;
    EXPECT_NE(message.find("LSDS_PLUGIN_DIR"), std::string::npos) << message;
  }
}

TEST(Plugin, ABrokenPlugInIsReportedWithTheLoadersReason) {
  testing::TempDir dir;
  const std::string path = (dir / imaging::kImageCodecsPlugin).string();
  std::ofstream(path) << "not a shared library\n";
  const ScopedPluginDir plugin_dir(dir.path().string());
  try {
    LoadPluginSymbol(imaging::kImageCodecsPlugin, imaging::kImageCodecsEntry);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cannot load the plug-in " + path), std::string::npos) << message;
    // dlerror()'s reason for a file that is not ELF.
    EXPECT_TRUE(message.find("invalid ELF header") != std::string::npos ||
                message.find("file too short") != std::string::npos)
        << message;
  }
}

TEST(Plugin, TheRealPlugInExportsItsTable) {
  const auto entry = reinterpret_cast<const imaging::ImageCodecsTable* (*)()>(
      LoadPluginSymbol(imaging::kImageCodecsPlugin, imaging::kImageCodecsEntry));
  ASSERT_NE(entry, nullptr);
  EXPECT_EQ(entry()->abi_version, imaging::kImageCodecsAbiVersion);
}

// Every plug-in's table is checked by one helper: another ABI version (a stale plug-in from an
// older install) or no table at all is an error naming the plug-in and both versions.
TEST(Plugin, AnotherAbiVersionIsAnErrorNamingThePlugIn) {
  const int stale = imaging::kImageCodecsAbiVersion + 1;
  try {
    CheckPluginAbiVersion(imaging::kImageCodecsPlugin, &stale, imaging::kImageCodecsAbiVersion);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              std::string("the plug-in lsds_image_codecs.so has ABI version ") +
                  std::to_string(stale) + ", lsds needs " +
                  std::to_string(imaging::kImageCodecsAbiVersion) + ": reinstall lsds");
  }
  EXPECT_THROW(
      CheckPluginAbiVersion(imaging::kImageCodecsPlugin, nullptr, imaging::kImageCodecsAbiVersion),
      Error);
  const int current = imaging::kImageCodecsAbiVersion;
  EXPECT_NO_THROW(CheckPluginAbiVersion(
      imaging::kImageCodecsPlugin, &current, imaging::kImageCodecsAbiVersion));
}

// The CLI: a command that writes images (export-layers to 16-bit PNG) with a broken plug-in stops
// with exit code 2 and the loader's message, and writes nothing. (`lsds report` instead shows the
// message in place of each picture, as for any picture it cannot make.)
TEST(Plugin, TheCliExitsTwoWhenThePlugInDoesNotLoad) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir / "plugins");
  std::ofstream((dir / "plugins" / imaging::kImageCodecsPlugin).string()) << "broken\n";
  const std::string plugins = "LSDS_PLUGIN_DIR=" + (dir / "plugins").string() + " ";
  const std::string collection = (dir / "c").string(), out = (dir / "layers").string();
  ASSERT_EQ(testing::RunLsds("synth -q --count 1 --size 16x12 " + collection).exit_code, 0);
  const testing::CommandResult result =
      testing::RunCommandLine(plugins + testing::LsdsBinary() + " export-layers -q --to png16 " +
                              collection + " -o " + out);
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("cannot load the plug-in"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace lsds
