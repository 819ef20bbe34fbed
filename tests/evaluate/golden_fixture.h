// The golden collection written once per build of the test binary, and its ground truth as
// lsds evaluate reads it (ReadCollectionTruth: the COCO converter in process).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "evaluate/ground_truth.h"
#include "evaluate/segmentation.h"
#include "libs/util/atomic_file.h"
#include "libs/util/json_errors.h"
#include "tests/build_paths.h"
#include "tests/evaluate/golden_collection.h"
#include "tests/test_util.h"

namespace lsds::evaluate {

// tests/evaluate/data/NAME: the committed prediction sets of the goldens.
inline std::filesystem::path GoldenData(const std::string& name) {
  return std::filesystem::path(testing::SourceDir()) / "tests" / "evaluate" / "data" / name;
}

// `lsds generate` of a scene and a capture given as text (written into `dir`
// as s.lscene and c.lcap) into dir/C at 1 spp, as a user runs it.
inline testing::CommandResult GenerateFromText(const std::filesystem::path& dir,
                                               const char* scene,
                                               const char* capture) {
  WriteFileAtomic(dir / "s.lscene", scene);
  WriteFileAtomic(dir / "c.lcap", capture);
  return testing::RunLsds("generate " + (dir / "s.lscene").string() + " " +
                          (dir / "c.lcap").string() + " -o " + (dir / "C").string() +
                          " --spp 1 -q");
}

// The crowd regions of a committed file (data/crowd_regions.json, or
// data/segm/crowd_regions.json with their masks) added to the ground truth.
inline void AddCrowdRegions(const std::string& name, EvaluationTruth* truth) {
  const std::string file = GoldenData(name).string();
  const nlohmann::json regions = ReadJsonFile(file);
  for (size_t i = 0; i < regions.size(); ++i) {
    const nlohmann::json& a = regions[i];
    GroundTruthBox g;
    g.id = a["id"].get<int64_t>();
    g.image_id = a["image_id"].get<int64_t>();
    g.category_id = a["category_id"].get<int64_t>();
    const nlohmann::json& b = a["bbox"];
    g.bbox = {b[0].get<double>(), b[1].get<double>(), b[2].get<double>(), b[3].get<double>()};
    g.area = a["area"].get<double>();
    g.iscrowd = a["iscrowd"].get<int>() != 0;
    if (truth->coco.iou_type == IouType::kMask) {
      const EvaluationTruth::ImageSize size = truth->SizeOf(g.image_id);
      g.mask = ReadSegmentation(a["segmentation"],
                                size.height,
                                size.width,
                                file,
                                "/" + std::to_string(i) + "/segmentation");
    }
    truth->coco.ground_truth.push_back(g);
  }
}

// The golden collection, written once per build of the test binary and shared by its tests. Each
// test runs in a process of its own (gtest_discover_tests), and writing the collection takes 0.6
// CPU s in Release but about 77 under the sanitizers, which made it most of the evaluate tests'
// time there. The folder is named by the binary's size and modification time, so a rebuilt binary
// (another spec, another synth) writes its own; of two processes writing at once, the first rename
// wins and the other's copy is dropped.
inline std::filesystem::path SharedGoldenCollection() {
  namespace fs = std::filesystem;
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  const std::string prefix = "golden_collection-" + exe.filename().string() + "-";
  const fs::path parent = fs::path(testing::BinaryDir()) / "tests" / "evaluate";
  const fs::path folder =
      parent /
      (prefix + std::to_string(fs::file_size(exe)) + "-" +
       std::to_string(static_cast<uint64_t>(fs::last_write_time(exe).time_since_epoch().count())));
  if (fs::exists(folder / "collection.json")) return folder;
  const fs::path staging = folder.string() + ".tmp" + std::to_string(::getpid());
  fs::remove_all(staging);
  synth::WriteCollection(staging, testing::EvaluateGoldenSpec());
  std::error_code ec;
  fs::rename(staging, folder, ec);
  if (ec) {
    fs::remove_all(staging);
    return folder;
  }
  // The copies of earlier builds of this binary (no process of theirs runs beside this one).
  for (const fs::directory_entry& entry : fs::directory_iterator(parent)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && entry.path() != folder &&
        name.find(".tmp") == std::string::npos)
      fs::remove_all(entry.path(), ec);
  }
  return folder;
}

class GoldenCollection : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    collection_ = new std::filesystem::path(SharedGoldenCollection());
    TruthOptions options;
    options.collection = *collection_;
    truth_ = new EvaluationTruth(ReadCollectionTruth(options));
    options.masks = true;
    mask_truth_ = new EvaluationTruth(ReadCollectionTruth(options));
  }
  static void TearDownTestSuite() {
    delete truth_;
    delete mask_truth_;
    delete collection_;
    truth_ = nullptr;
    mask_truth_ = nullptr;
    collection_ = nullptr;
  }
  static std::string C() { return collection_->string(); }

  inline static std::filesystem::path* collection_ = nullptr;
  inline static EvaluationTruth* truth_ = nullptr;       // boxes (iouType bbox)
  inline static EvaluationTruth* mask_truth_ = nullptr;  // with masks (iouType segm)
};

}  // namespace lsds::evaluate
