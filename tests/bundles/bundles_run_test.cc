// lsds bundles on synthetic collections (synth): statistics JSON, derived
// layers registered and readable, inputs unchanged, clear errors.
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "bundles/bundle_run.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/schema.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "synth/synthetic_collection.h"
#include "tests/build_paths.h"

namespace lsds::bundle {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() / ("lsds_bundles_test_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Every file under `root` with its content.
std::map<std::string, std::string> Snapshot(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.is_regular_file()) {
      files[fs::relative(entry.path(), root).string()] = ReadFile(entry.path());
    }
  }
  return files;
}

synth::Spec SmallSpec() {
  synth::Spec spec = synth::DefaultSpec();
  spec.width = 48;
  spec.height = 36;
  return spec;
}

int RunLsds(const std::string& args, std::string* output) {
  const std::string out_file =
      // Per process: suites of several checkouts may run at once.
      (fs::temp_directory_path() / ("lsds_bundles_cli_out_" + std::to_string(getpid()) + ".txt"))
          .string();
  const std::string command =
      ::lsds::testing::BinaryDir() + "/tools/lsds " + args + " > " + out_file + " 2>&1";
  const int status = std::system(command.c_str());
  *output = ReadFile(out_file);
  fs::remove(out_file);
  return WEXITSTATUS(status);
}

TEST(BundlesRun, WritesStatisticsThatPassTheSchema) {
  TempDir dir;
  const fs::path root = dir.path() / "c";
  synth::WriteCollection(root, SmallSpec());
  const auto before = Snapshot(root);
  RunOptions options;
  options.output = dir.path() / "stats.json";
  const RunResult result = RunBundles(root, options);
  EXPECT_EQ(Snapshot(root),
            before);  // statistics alone touch nothing in the collection
  EXPECT_EQ(result.frames_analyzed, 4);
  EXPECT_EQ(result.total.pixels, 4u * 48 * 36);
  EXPECT_GT(result.total.mixed_pixels, 0u);  // box edges against the ground
  EXPECT_LT(result.total.mixed_pixels, result.total.pixels / 2);

  const nlohmann::json stats = nlohmann::json::parse(ReadFile(options.output));
  EXPECT_TRUE(JsonSchema::Get("bundle-stats.schema.json").Validate(stats).empty());
  EXPECT_EQ(stats["frames"].size(), 4u);
  EXPECT_EQ(stats["summary"]["mixed_pixels"].get<uint64_t>(), result.total.mixed_pixels);
  uint64_t per_frame = 0;
  for (const auto& frame : stats["frames"])
    per_frame += frame["stats"]["mixed_pixels"].get<uint64_t>();
  EXPECT_EQ(per_frame, result.total.mixed_pixels);
  EXPECT_FALSE(stats["objects"].empty());
}

TEST(BundlesRun, WrittenLayersAreRegisteredReadableAndInputsUnchanged) {
  TempDir dir;
  const fs::path root = dir.path() / "c";
  synth::WriteCollection(root, SmallSpec());
  const auto before = Snapshot(root);
  const CollectionReader original(root);

  RunOptions options;
  options.write_layers = {"majority", "purity", "coverage", "edge"};
  RunBundles(root, options);

  // Every earlier file is byte-identical, except collection.json which gained
  // the new layers.
  const auto after = Snapshot(root);
  for (const auto& [file, content] : before) {
    if (file == "collection.json") continue;
    ASSERT_TRUE(after.count(file)) << file;
    EXPECT_EQ(after.at(file), content) << file;
  }

  const CollectionReader reader(root);  // passes the schema
  const CollectionHeader& header = reader.header();
  ASSERT_EQ(header.layers.size(), original.header().layers.size() + 4);
  for (size_t i = 0; i < original.header().layers.size(); ++i) {
    EXPECT_EQ(header.layers[i].name, original.header().layers[i].name);
    EXPECT_EQ(header.layers[i].semantic, original.header().layers[i].semantic);
  }
  for (const char* name : {"majority", "purity", "coverage", "edge"}) {
    const LayerInfo* layer = header.FindLayer(name);
    ASSERT_NE(layer, nullptr) << name;
    EXPECT_EQ(layer->semantic, "derived");
    EXPECT_TRUE(layer->required);
  }
  EXPECT_TRUE(header.FindLayer("coverage")->deep);

  int frames = 0;
  reader.ForEachFrame([&](const Frame& frame) {
    ++frames;
    const exr::DeepImage bundle = ReadBundleExr(reader.LayerPath(frame, "bundle"));
    const exr::FlatImage majority = exr::ReadFlatExr(reader.LayerPath(frame, "majority"));
    const exr::FlatImage purity = exr::ReadFlatExr(reader.LayerPath(frame, "purity"));
    const exr::FlatImage edge = exr::ReadFlatExr(reader.LayerPath(frame, "edge"));
    const exr::DeepImage coverage = exr::ReadDeepExr(reader.LayerPath(frame, "coverage"));
    ASSERT_EQ(majority.width(), bundle.width());
    const auto& ids = bundle.Get("instanceid").uints;
    const auto& shares = coverage.Get("coverage").floats;
    for (int y = 0; y < bundle.height(); ++y) {
      for (int x = 0; x < bundle.width(); ++x) {
        const size_t p = bundle.Index(x, y);
        const float pur = purity.Get("Y").floats[p];
        const uint32_t n = bundle.SampleCount(x, y);
        // Coverage shares sum to 1; the first is the purity and its id the
        // majority id.
        double sum = 0;
        for (uint32_t s = 0; s < coverage.SampleCount(x, y); ++s)
          sum += shares[coverage.FirstSample(x, y) + s];
        EXPECT_NEAR(sum, 1.0, 1e-6);
        EXPECT_EQ(shares[coverage.FirstSample(x, y)], pur);
        EXPECT_EQ(coverage.Get("instanceid").uints[coverage.FirstSample(x, y)],
                  majority.Get("instanceid").uints[p]);
        bool uniform = true;
        for (uint32_t s = 1; s < n; ++s)
          uniform &= ids[bundle.FirstSample(x, y) + s] == ids[bundle.FirstSample(x, y)];
        EXPECT_EQ(pur == 1.0f, uniform);
        if (uniform) {
          EXPECT_EQ(majority.Get("instanceid").uints[p], ids[bundle.FirstSample(x, y)]);
        } else {
          EXPECT_EQ(edge.Get("Y").uints[p], 1u);
        }
      }
    }
  });
  EXPECT_EQ(frames, 4);
}

TEST(BundlesRun, RefusesToReplaceLayersWithoutForce) {
  TempDir dir;
  const fs::path root = dir.path() / "c";
  synth::WriteCollection(root, SmallSpec());
  RunOptions options;
  options.write_layers = {"purity"};
  RunBundles(root, options);
  const std::string table = ReadFile(root / "collection.json");
  EXPECT_THROW(RunBundles(root, options), Error);
  EXPECT_EQ(ReadFile(root / "collection.json"), table);
  options.force = true;
  EXPECT_NO_THROW(RunBundles(root, options));
  EXPECT_EQ(CollectionReader(root).header().layers.size(),
            CollectionReader(root).header().layers.size());
}

TEST(BundlesRun, ForceReplacesTheFolderOfAnInterruptedRunAndNothingElse) {
  TempDir dir;
  const fs::path root = dir.path() / "c";
  synth::WriteCollection(root, SmallSpec());
  const std::string before = ReadFile(root / "collection.json");
  RunOptions options;
  options.write_layers = {"purity"};
  RunBundles(root, options);
  const std::map<std::string, std::string> complete = Snapshot(root);
  // A kill -9 between renaming the folder into place and registering it:
  // the folder is there, collection.json is the old one.
  WriteFileAtomic(root / "collection.json", before);
  try {
    RunBundles(root, options);
    ADD_FAILURE() << "an unregistered folder was replaced without --force";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("interrupted"), std::string::npos) << e.what();
  }
  options.force = true;
  RunBundles(root, options);
  EXPECT_EQ(Snapshot(root), complete);

  // A folder of that name that lsds did not write is never replaced: here an
  // EXR of another layer.
  fs::create_directories(root / "edge");
  fs::copy_file(root / "purity" / fs::directory_iterator(root / "purity")->path().filename(),
                root / "edge" / "000000.exr");
  options.write_layers = {"edge"};
  EXPECT_THROW(RunBundles(root, options), Error);
  EXPECT_TRUE(fs::exists(root / "edge" / "000000.exr"));
}

TEST(BundlesRun, FrameRangeWritesOptionalLayers) {
  TempDir dir;
  const fs::path root = dir.path() / "c";
  synth::WriteCollection(root, SmallSpec());
  RunOptions options;
  options.write_layers = {"edge"};
  options.frames = FrameRange{1, 3};
  const RunResult result = RunBundles(root, options);
  EXPECT_EQ(result.frames_analyzed, 2);
  const CollectionReader reader(root);
  EXPECT_FALSE(reader.header().FindLayer("edge")->required);
  int with_edge = 0;
  reader.ForEachFrame([&](const Frame& frame) { with_edge += frame.files.count("edge"); });
  EXPECT_EQ(with_edge, 2);
}

TEST(BundlesRun, CollectionWithoutBundleSaysHowToMakeOne) {
  TempDir dir;
  const fs::path root = dir.path() / "c";
  synth::Spec spec = SmallSpec();
  spec.layers = {"rgb", "classid", "instanceid", "depth"};
  synth::WriteCollection(root, spec);
  try {
    RunBundles(root, RunOptions());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("lsds generate --spp"), std::string::npos) << e.what();
  }
}

TEST(BundlesCli, RunsEndToEndAndMapsErrorsToExitCodes) {
  TempDir dir;
  const fs::path root = dir.path() / "c";
  synth::WriteCollection(root, SmallSpec());
  std::string out;
  const fs::path stats = dir.path() / "s.json";
  const fs::path png = dir.path() / "mixed.png";
  EXPECT_EQ(RunLsds("bundles " + root.string() + " -o " + stats.string() + " --mixed-map " +
                        png.string() + " --frames 0:2",
                    &out),
            0)
      << out;
  EXPECT_NE(out.find("mixed pixels"), std::string::npos);
  EXPECT_TRUE(fs::exists(stats));
  EXPECT_GT(fs::file_size(png), 0u);
  // Existing output without --force.
  EXPECT_EQ(RunLsds("bundles " + root.string() + " -o " + stats.string(), &out), 2);
  EXPECT_EQ(RunLsds("bundles " + root.string() + " --write-layers majorty", &out), 2);
  EXPECT_NE(out.find("did you mean 'majority'"), std::string::npos) << out;
  EXPECT_EQ(RunLsds("bundles " + root.string() + " --frames 5:2", &out), 2);
  EXPECT_EQ(RunLsds("bundles " + (dir.path() / "nothing").string(), &out), 2);
}

}  // namespace
}  // namespace lsds::bundle
