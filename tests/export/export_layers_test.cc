// lsds export-layers end to end: a synthetic collection exported by the CLI,
// every file read back the way a user reads it (a .npy header parsed here and
// numpy.load when installed; cv::imread IMREAD_UNCHANGED for PNG and TIFF) and
// compared with the EXR layers: .npy and TIFF bit for bit, 16-bit PNG within the
// half step that layers.json documents.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/util/strings.h"
#include "synth/synthetic_collection.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;

std::string Slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A .npy file parsed by the rules of numpy.lib.format (version 1.0).
struct Npy {
  std::string descr;
  bool fortran_order = true;
  std::vector<int64_t> shape;
  std::string data;
};

Npy ReadNpy(const fs::path& path) {
  const std::string bytes = Slurp(path);
  Npy npy;
  EXPECT_GE(bytes.size(), 10u) << path;
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8)) << path;
  const size_t length =
      static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
  const std::string dict = bytes.substr(10, length);
  std::smatch m;
  if (std::regex_search(dict, m, std::regex("'descr': '([^']+)'"))) npy.descr = m[1];
  npy.fortran_order = dict.find("'fortran_order': False") == std::string::npos;
  if (std::regex_search(dict, m, std::regex("'shape': \\(([^)]*)\\)"))) {
    for (const std::string& part : Split(m[1], ','))
      if (part.find_first_not_of(' ') != std::string::npos) npy.shape.push_back(std::stoll(part));
  }
  npy.data = bytes.substr(10 + length);
  return npy;
}

// A file of layers.json ("depth/{stem}.png") for frame `index`.
std::string FileOfFrame(const fs::path& out, const nlohmann::json& pattern, int64_t index) {
  return (out / std::regex_replace(
                    pattern.get<std::string>(), std::regex("\\{stem\\}"), FrameStem(index)))
      .string();
}

nlohmann::json ReadSidecar(const fs::path& out) {
  return nlohmann::json::parse(Slurp(out / "layers.json"));
}

// The bits of one channel of a layer's EXR as 32-bit words (floats or uints).
std::vector<uint32_t> ExrWords(const exr::FlatImage& image, const std::string& channel) {
  const exr::FlatChannel& c = image.Get(channel);
  std::vector<uint32_t> words(image.pixel_count());
  if (!c.uints.empty())
    std::memcpy(words.data(), c.uints.data(), words.size() * 4);
  else
    std::memcpy(words.data(), c.floats.data(), words.size() * 4);
  return words;
}

class ExportLayers : public ::testing::Test {
 protected:
  void SetUp() override { Write(synth::DefaultSpec()); }

  void Write(const synth::Spec& spec) {
    fs::remove_all(collection_);
    synth::WriteCollection(collection_, spec);
  }

  CommandResult Run(const std::string& args) {
    return RunCommandLine(LsdsBinary() + " export-layers " + collection_.string() + " " + args);
  }

  // Each frame's EXR of `layer`, by frame index.
  std::map<int64_t, exr::FlatImage> Exrs(const std::string& layer) const {
    const CollectionReader reader(collection_);
    std::map<int64_t, exr::FlatImage> images;
    reader.ForEachFrame([&](const Frame& frame) {
      images[frame.index] = exr::ReadFlatExr(reader.LayerPath(frame, layer));
    });
    return images;
  }

  std::vector<const LayerInfo*> FlatLayers() {
    header_ = CollectionReader(collection_).header();
    std::vector<const LayerInfo*> layers;
    for (const LayerInfo& l : header_.layers)
      if (!l.deep) layers.push_back(&l);
    return layers;
  }

  TempDir dir_;
  fs::path collection_ = dir_ / "collection";
  fs::path out_ = dir_ / "out";
  CollectionHeader header_;
};

TEST_F(ExportLayers, NpyHoldsTheExrValuesBitForBitWithTheirDtypeAndShape) {
  const CommandResult run = Run("-o " + out_.string() + " --frames 1:3");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json sidecar = ReadSidecar(out_);
  EXPECT_EQ(sidecar["to"], "npy");
  EXPECT_EQ(sidecar["frames"], nlohmann::json::array({1, 2}));
  EXPECT_FALSE(fs::exists(out_ / "bundle")) << "deep layers are not exported";
  const std::vector<const LayerInfo*> layers = FlatLayers();
  ASSERT_GE(layers.size(), 8u);  // rgb, ids, depth, normal, position, ...
  for (const LayerInfo* layer : layers) {
    SCOPED_TRACE(layer->name);
    ASSERT_TRUE(sidecar["layers"].contains(layer->name));
    const nlohmann::json& entry = sidecar["layers"][layer->name];
    const bool ids = layer->channels[0].type == exr::PixelType::kUint;
    EXPECT_EQ(entry["dtype"], ids ? "uint32" : "float32");
    EXPECT_EQ(entry["unit"], layer->unit);
    EXPECT_EQ(entry["frames_written"], 2);
    EXPECT_FALSE(fs::exists(out_ / layer->name / "000000.npy"));
    for (const auto& [index, image] : Exrs(layer->name)) {
      if (index < 1 || index >= 3) continue;
      const Npy npy = ReadNpy(out_ / layer->name / (FrameStem(index) + ".npy"));
      EXPECT_EQ(npy.descr, ids ? "<u4" : "<f4");
      EXPECT_FALSE(npy.fortran_order);
      std::vector<int64_t> shape = {image.height(), image.width()};
      const size_t channels = layer->channels.size();
      if (channels > 1) shape.push_back(static_cast<int64_t>(channels));
      EXPECT_EQ(npy.shape, shape);
      ASSERT_EQ(npy.data.size(), image.pixel_count() * channels * 4);
      // Interleaved (height, width, channels) in the layer table's order.
      std::vector<uint32_t> words(image.pixel_count() * channels);
      std::memcpy(words.data(), npy.data.data(), npy.data.size());
      for (size_t c = 0; c < channels; ++c) {
        const std::vector<uint32_t> exr = ExrWords(image, layer->channels[c].name);
        size_t differ = 0;
        for (size_t p = 0; p < exr.size(); ++p)
          if (words[p * channels + c] != exr[p]) ++differ;
        EXPECT_EQ(differ, 0u) << "frame " << index << " channel " << layer->channels[c].name;
      }
    }
  }
}

TEST_F(ExportLayers, NumpyLoadReadsTheSameArrays) {
  // Debian's python3 (python3-numpy), not whatever python3 comes first on PATH.
  const std::string python = "/usr/bin/python3";
  if (RunCommandLine(python + " -c 'import numpy'").exit_code != 0)
    GTEST_SKIP() << "python3-numpy is not installed (scripts/install-deps.sh)";
  ASSERT_EQ(Run("-o " + out_.string() + " --layers depth,normal,instanceid").exit_code, 0);
  // numpy writes what it loaded as raw C-order bytes plus dtype and shape.
  const std::string script =
      "import numpy as np, sys\n"
      "for name in sys.argv[1:]:\n"
      "    a = np.load(name)\n"
      "    open(name + '.raw', 'wb').write(np.ascontiguousarray(a).tobytes())\n"
      "    print(name, a.dtype.str, a.shape)\n";
  std::ofstream(dir_ / "load.py") << script;
  const std::vector<std::string> files = {
      "depth/000002.npy", "normal/000002.npy", "instanceid/000002.npy"};
  std::string args;
  for (const std::string& f : files) args += " " + (out_ / f).string();
  const CommandResult loaded = RunCommandLine(python + " " + (dir_ / "load.py").string() + args);
  ASSERT_EQ(loaded.exit_code, 0) << loaded.output;
  EXPECT_NE(loaded.output.find("depth/000002.npy <f4 (48, 64)"), std::string::npos)
      << loaded.output;
  EXPECT_NE(loaded.output.find("normal/000002.npy <f4 (48, 64, 3)"), std::string::npos);
  EXPECT_NE(loaded.output.find("instanceid/000002.npy <u4 (48, 64)"), std::string::npos);
  for (const std::string& f : files) {
    const Npy npy = ReadNpy(out_ / f);
    EXPECT_EQ(Slurp(out_ / (f + ".raw")), npy.data) << f;
  }
}

TEST_F(ExportLayers, Png16DecodesWithinHalfAStepWithInvalidPixelsMarked) {
  const CommandResult run = Run("-o " + out_.string() + " --to png16");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json sidecar = ReadSidecar(out_);
  // Unbounded or HDR layers have no 16-bit encoding and are left out.
  EXPECT_FALSE(sidecar["layers"].contains("worldposition"));
  EXPECT_FALSE(sidecar["layers"].contains("rgb"));
  for (const std::string name : {"classid", "instanceid", "depth", "normal", "shadow", "motion"}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(sidecar["layers"].contains(name));
    const nlohmann::json& entry = sidecar["layers"][name];
    EXPECT_EQ(entry["dtype"], "uint16");
    EXPECT_EQ(entry["clamped_pixels"].get<int64_t>(), 0);
    const double scale = entry["scale"], offset = entry["offset"];
    const bool has_invalid = entry["invalid"].is_object();
    const int invalid = has_invalid ? entry["invalid"]["stored"].get<int>() : -1;
    int64_t invalid_seen = 0;
    for (const auto& [index, image] : Exrs(name)) {
      for (const auto& [channel, file] : entry["files"].items()) {
        const std::string path = FileOfFrame(out_, file, index);
        const cv::Mat png = cv::imread(path, cv::IMREAD_UNCHANGED);
        ASSERT_EQ(png.type(), CV_16UC1) << path;
        ASSERT_EQ(png.cols, image.width());
        const exr::FlatChannel& exr = image.Get(channel);
        double worst = 0;
        for (size_t p = 0; p < image.pixel_count(); ++p) {
          const uint16_t stored = png.ptr<uint16_t>()[p];
          if (!exr.uints.empty()) {
            ASSERT_EQ(stored, exr.uints[p]) << path << " pixel " << p;
            continue;
          }
          const float truth = exr.floats[p];
          if (stored == invalid) {
            ASSERT_FALSE(std::isfinite(truth)) << path << " pixel " << p;
            ++invalid_seen;
            continue;
          }
          ASSERT_TRUE(std::isfinite(truth)) << path << " pixel " << p;
          worst = std::max(worst, std::abs(stored * scale + offset - truth));
        }
        // Half a step, plus the float32 rounding of the EXR value itself.
        EXPECT_LE(worst, scale / 2 * (1 + 1e-6) + 1e-6) << path;
      }
    }
    EXPECT_EQ(invalid_seen, entry["invalid_pixels"].get<int64_t>());
    if (name == "motion") {
      EXPECT_GT(invalid_seen, 0) << "frame 0 is NaN";
    }
  }
  // The documented decoding of the encodings that are exact at their centre.
  EXPECT_EQ(sidecar["layers"]["depth"]["scale"], 0.001);
  EXPECT_EQ(sidecar["layers"]["normal"]["offset"].get<double>() +
                32768 * sidecar["layers"]["normal"]["scale"].get<double>(),
            0.0);
}

TEST_F(ExportLayers, Png16MarksSkyDepthInvalidAndClampsAndCountsFarDepth) {
  synth::Spec spec = synth::DefaultSpec();
  spec.ground = false;  // sky around the boxes: +inf depth
  Write(spec);
  CommandResult run = Run("-o " + out_.string() + " --to png16 --layers depth --frames 0");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const cv::Mat sky = cv::imread((out_ / "depth/000000.png").string(), cv::IMREAD_UNCHANGED);
  const exr::FlatImage exr = Exrs("depth").at(0);
  int64_t invalid = 0;
  for (size_t p = 0; p < exr.pixel_count(); ++p) {
    const bool is_sky = std::isinf(exr.Get("Z").floats[p]);
    EXPECT_EQ(sky.ptr<uint16_t>()[p] == 0, is_sky) << p;
    invalid += is_sky;
  }
  EXPECT_GT(invalid, 0);
  EXPECT_EQ(ReadSidecar(out_)["layers"]["depth"]["invalid_pixels"], invalid);

  // 0.1 mm steps reach 6.55 m only: the boxes' tops at ~18 m do not fit. That is an error naming
  // the frame, the pixel and a step that fits, and the output of the run before stays.
  run = Run("-o " + out_.string() +
            " --to png16 --layers depth --frames 0 --depth-step 0.0001 --force");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("is beyond the 16-bit PNG range of --depth-step 0.0001"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("use --depth-step 0.0005 or more"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("frame 0"), std::string::npos) << run.output;
  EXPECT_EQ(ReadSidecar(out_)["layers"]["depth"]["scale"], 0.001);
  // --clamp-depth clamps them to the last step, counted and warned about.
  run = Run("-o " + out_.string() +
            " --to png16 --layers depth --frames 0 --depth-step 0.0001 --clamp-depth --force");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("clamped"), std::string::npos) << run.output;
  const nlohmann::json entry = ReadSidecar(out_)["layers"]["depth"];
  EXPECT_EQ(entry["clamped_pixels"], exr.pixel_count() - invalid);
  EXPECT_EQ(entry["scale"], 0.0001);
  const cv::Mat clamped = cv::imread((out_ / "depth/000000.png").string(), cv::IMREAD_UNCHANGED);
  for (size_t p = 0; p < exr.pixel_count(); ++p)
    if (!std::isinf(exr.Get("Z").floats[p])) {
      EXPECT_EQ(clamped.ptr<uint16_t>()[p], 65535);
    }
}

TEST_F(ExportLayers, TiffHoldsTheExrValuesBitForBitOneFilePerChannel) {
  const CommandResult run =
      Run("-o " + out_.string() + " --to tiff --layers depth,normal,instanceid");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json sidecar = ReadSidecar(out_);
  EXPECT_EQ(sidecar["layers"].size(), 3u);
  EXPECT_EQ(sidecar["layers"]["instanceid"]["dtype"], "int32");
  EXPECT_EQ(sidecar["layers"]["normal"]["files"]["Y"], "normal/{stem}.Y.tiff");
  for (const std::string name : {"depth", "normal", "instanceid"}) {
    const nlohmann::json& entry = sidecar["layers"][name];
    for (const auto& [index, image] : Exrs(name)) {
      for (const auto& [channel, file] : entry["files"].items()) {
        const std::string path = FileOfFrame(out_, file, index);
        const cv::Mat tiff = cv::imread(path, cv::IMREAD_UNCHANGED);
        ASSERT_EQ(tiff.type(), name == "instanceid" ? CV_32SC1 : CV_32FC1) << path;
        ASSERT_EQ(tiff.total(), image.pixel_count());
        const std::vector<uint32_t> exr = ExrWords(image, channel);
        EXPECT_EQ(std::memcmp(tiff.data, exr.data(), exr.size() * 4), 0) << path;
      }
    }
  }
}

TEST_F(ExportLayers, RefusesBadUsageWithTheDocumentedMessages) {
  auto expect_usage = [&](const std::string& args, const std::string& says) {
    const CommandResult run = Run(args);
    EXPECT_EQ(run.exit_code, 2) << args << "\n" << run.output;
    EXPECT_NE(run.output.find(says), std::string::npos) << args << "\n" << run.output;
    EXPECT_NE(run.output.find("lsds export-layers: error:"), std::string::npos) << run.output;
  };
  expect_usage("-o " + (collection_ / "exported").string(),
               "the output (-o) lies inside the collection folder");
  EXPECT_FALSE(fs::exists(collection_ / "exported"));
  expect_usage("-o " + dir_.path().string(), "the output (-o) contains the collection");
  expect_usage("-o " + out_.string() + " --layers dept", "did you mean 'depth'");
  expect_usage("-o " + out_.string() + " --layers bundle", "deep layer");
  expect_usage("-o " + out_.string() + " --to png16 --layers worldposition",
               "use --to npy or --to tiff");
  expect_usage("-o " + out_.string() + " --frames 7:9", "--frames");
  EXPECT_FALSE(fs::exists(out_));

  // An existing output is kept without --force and replaced with it.
  ASSERT_EQ(Run("-o " + out_.string() + " --layers depth").exit_code, 0);
  expect_usage("-o " + out_.string() + " --layers normal", "--force");
  EXPECT_TRUE(fs::exists(out_ / "depth"));
  ASSERT_EQ(Run("-o " + out_.string() + " --layers normal --force").exit_code, 0);
  EXPECT_FALSE(fs::exists(out_ / "depth"));
  EXPECT_TRUE(fs::exists(out_ / "normal/000003.npy"));
}

TEST_F(ExportLayers, Png16RefusesIdsAbove65535NamingFrameAndPixel) {
  synth::Spec spec = synth::DefaultSpec();
  spec.boxes[0].instance_id = 70000;
  Write(spec);
  const CommandResult run = Run("-o " + out_.string() + " --to png16 --layers instanceid");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("id 70000"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("pixel ("), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("frame "), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out_)) << "nothing partial is left behind";
  // npy holds them exactly.
  ASSERT_EQ(Run("-o " + out_.string() + " --layers instanceid").exit_code, 0);
}

}  // namespace
}  // namespace lsds::testing
