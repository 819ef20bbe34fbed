// Hostile sources for every importer (docs/import.md, "Confinement" and
// "Numbers and ids"): names in a source's data that are absolute or climb out
// with "..", symbolic links out of the source, numbers written as text that do
// not fit, ids outside [0, 2^32), values of the wrong type and NaN depth all
// stop the import with an lsds::Error naming the file and the place, and
// nothing is written. --allow-links-outside reads deliberately linked data.
#include <sys/stat.h>

#include <cmath>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "importers/import_collection.h"
#include "importers/source_json.h"
#include "libs/exr/flat_image.h"
#include "libs/util/confined_path.h"
#include "libs/util/error.h"
#include "libs/util/text_check.h"
#include "tests/import/airsim_fixture.h"
#include "tests/import/bop_fixture.h"
#include "tests/import/import_checks.h"
#include "tests/import/kubric_fixture.h"
#include "tests/import/mrq_fixture.h"
#include "tests/import/replicator_fixture.h"
#include "tests/import/solo_fixture.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The message of the lsds::Error `body` throws ("" when it throws none).
template <typename F>
std::string ErrorOf(F&& body) {
  try {
    body();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

void ExpectHas(const std::string& message, const std::vector<std::string>& parts) {
  EXPECT_FALSE(message.empty()) << "no error";
  for (const std::string& part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
}

json ReadJson(const fs::path& path) { return json::parse(ReadText(path)); }
void WriteJson(const fs::path& path, const json& j) { std::ofstream(path) << j.dump(); }

// A file outside every source: what a hostile link points at.
fs::path OutsideCopyOf(const fs::path& file, const fs::path& dir) {
  const fs::path outside = dir / ("outside" + file.extension().string());
  fs::copy_file(file, outside, fs::copy_options::overwrite_existing);
  return outside;
}

void ReplaceWithLink(const fs::path& file, const fs::path& target) {
  fs::remove(file);
  fs::create_symlink(target, file);
}

// --- the rule itself ----------------------------------------------------------

TEST(Confinement, ReferencesMustBeRelativeAndStayInside) {
  EXPECT_EQ(ReferenceProblem("a/b.png", "the source"), "");
  EXPECT_EQ(ReferenceProblem("a b/c..d.png", "the source"), "");
  EXPECT_EQ(ReferenceProblem("", "the source"), "is empty");
  EXPECT_EQ(ReferenceProblem("/etc/hostname", "the source"), "is absolute");
  EXPECT_EQ(ReferenceProblem("\\\\server\\x", "the source"), "is absolute");
  EXPECT_EQ(ReferenceProblem("C:\\x.png", "the source"), "is absolute");
  EXPECT_EQ(ReferenceProblem("../x.png", "the source"), "leaves the source (\"..\")");
  EXPECT_EQ(ReferenceProblem("a\\..\\..\\x.png", "the source"), "leaves the source (\"..\")");
  EXPECT_EQ(ReferenceProblem(std::string("a\0b", 3), "the source"), "holds a NUL byte");
}

TEST(Confinement, LinksMustResolveInsideUnlessAllowed) {
  TempDir dir;
  const fs::path root = dir / "source";
  fs::create_directories(root / "images");
  std::ofstream(root / "images" / "a.png") << "a";
  std::ofstream(dir / "secret.txt") << "secret";
  fs::create_symlink("a.png", root / "images" / "inside.png");
  fs::create_symlink(dir / "secret.txt", root / "images" / "out.png");
  fs::create_directory_symlink(dir.path(), root / "up");
  const ConfinedFolder strict(root);
  const Location where("data.json", "/captures/0/filename");

  EXPECT_EQ(strict.Reference(root / "images", "a.png", where), root / "images" / "a.png");
  EXPECT_EQ(strict.Reference(root / "images", "inside.png", where), root / "images" / "inside.png");
  EXPECT_EQ(strict.Reference(root, "missing.png", where), root / "missing.png");  // reader says
  ExpectHas(ErrorOf([&] { strict.Reference(root, "/etc/hostname", where); }),
            {"data.json#/captures/0/filename", "'/etc/hostname' is absolute"});
  ExpectHas(ErrorOf([&] { strict.Reference(root / "images", "../../secret.txt", where); }),
            {"data.json#/captures/0/filename", "leaves the source"});
  ExpectHas(ErrorOf([&] { strict.Reference(root / "images", "out.png", where); }),
            {"data.json#/captures/0/filename", "out.png", "secret.txt", "--allow-links-outside"});
  ExpectHas(ErrorOf([&] { strict.File(root / "up" / "secret.txt"); }),
            {"outside the source folder"});

  const ConfinedFolder linked(root, true);
  EXPECT_EQ(linked.Reference(root / "images", "out.png", where), root / "images" / "out.png");
  EXPECT_EQ(linked.File(root / "up" / "secret.txt"), root / "up" / "secret.txt");
  // The flag is about links only: names in data still stay inside.
  ExpectHas(ErrorOf([&] { linked.Reference(root, "../secret.txt", where); }),
            {"leaves the source"});
  ExpectHas(ErrorOf([&] { linked.Reference(root, "/etc/hostname", where); }), {"is absolute"});
}

TEST(Confinement, AFifoOrAFolderIsRefusedBeforeItIsOpened) {
  TempDir dir;
  ASSERT_EQ(mkfifo((dir / "pipe.png").c_str(), 0600), 0);
  fs::create_directories(dir / "folder.png");
  const ConfinedFolder root(dir.path());
  ExpectHas(ErrorOf([&] { root.File(dir / "pipe.png"); }), {"pipe.png", "not a regular file"});
  ExpectHas(ErrorOf([&] { root.File(dir / "folder.png"); }), {"folder.png", "a folder"});
}

// --- the checked numbers ------------------------------------------------------

TEST(CheckedNumbers, TextIntegersAreParsedWholeAndInRange) {
  const int64_t max = std::numeric_limits<int64_t>::max();
  EXPECT_EQ(ParseInteger("0042", 0, max), 42);
  EXPECT_EQ(ParseInteger("-1", -5, 5), -1);
  EXPECT_EQ(ParseInteger("-1", 0, max), std::nullopt);
  EXPECT_EQ(ParseInteger("4294967297", 1, 4294967295), std::nullopt);
  EXPECT_EQ(ParseInteger("99999999999999999999", 0, max), std::nullopt);
  for (const char* bad : {"", "-", "+1", " 1", "1 ", "1a", "0x10", "1.0", "1e3"})
    EXPECT_EQ(ParseInteger(bad, -max, max), std::nullopt) << bad;
}

TEST(CheckedNumbers, IdsOutsideUint32AreLocatedErrors) {
  using import::IdAt;
  EXPECT_EQ(IdAt(json(7), "f.json", "/id"), 7u);
  EXPECT_EQ(IdAt(json(7.0), "f.json", "/id"), 7u);
  EXPECT_EQ(IdAt(json(4294967295u), "f.json", "/id"), 4294967295u);
  ExpectHas(ErrorOf([] { IdAt(json(4294967298u), "f.json", "/classes/0/id"); }),
            {"f.json#/classes/0/id", "4294967298", "[0, 4294967295]"});
  ExpectHas(ErrorOf([] { IdAt(json(-1), "f.json", "/id"); }), {"f.json#/id", "-1"});
  ExpectHas(ErrorOf([] { IdAt(json(2.5), "f.json", "/id"); }), {"f.json#/id", "2.5"});
  ExpectHas(ErrorOf([] { IdAt(json(1e300), "f.json", "/id"); }), {"f.json#/id"});
  ExpectHas(ErrorOf([] { IdAt(json("1"), "f.json", "/id"); }), {"f.json#/id", "\"1\""});
  ExpectHas(ErrorOf([] { import::StringAt(json(5), "f.json", "/name"); }),
            {"f.json#/name", "expected a string"});
}

// --- each importer ------------------------------------------------------------

class HostileImportTest : public ::testing::Test {
 protected:
  HostileImportTest() {
    spec_.cam_from_world.resize(2);
    spec_.samples_per_axis = 1;
  }
  // Imports `source`, expecting a located error holding `parts`, and no output.
  void ExpectRefused(const std::string& format,
                     const fs::path& source,
                     const std::vector<std::string>& parts,
                     const import::ImportOptions& options = {}) {
    const fs::path out = dir_ / "out";
    ExpectHas(ErrorOf([&] { import::ImportCollection(format, source, out, options, false); }),
              parts);
    EXPECT_FALSE(fs::exists(out));
  }
  void ExpectImports(const std::string& format,
                     const fs::path& source,
                     const import::ImportOptions& options) {
    const fs::path out = dir_ / "imported";
    EXPECT_EQ(import::ImportCollection(format, source, out, options, false).frames, 2);
    fs::remove_all(out);
  }

  TempDir dir_;
  synth::Spec spec_ = ObliqueImportSpec();
};

TEST_F(HostileImportTest, SoloNamesClimbingOutLinksIdsAndNanDepth) {
  const fs::path solo = dir_ / "solo";
  WriteSoloFixture(solo, spec_, 1);
  const fs::path step = solo / "sequence.0" / "step0.frame_data.json";
  const json original = ReadJson(step);
  const auto with = [&](const std::string& pointer, const json& value) {
    json data = original;
    data[json::json_pointer(pointer)] = value;
    WriteJson(step, data);
  };
  with("/captures/0/filename", "/etc/hostname");
  ExpectRefused("solo", solo, {"step0.frame_data.json#/captures/0/filename", "is absolute"});
  with("/captures/0/filename", "../sequence.1/step0.camera.png");
  ExpectRefused("solo", solo, {"step0.frame_data.json#/captures/0/filename", "leaves the source"});
  with("/captures/0/filename", 7);
  ExpectRefused("solo", solo, {"#/captures/0/filename", "expected a string"});
  with("/captures/0/annotations/0/instances/0/instanceId", -1);
  ExpectRefused("solo", solo, {"#/captures/0/annotations/0/instances/0/instanceId", "-1"});
  with("/captures/0/annotations/1/values/0/labelId", 4294967298u);
  ExpectRefused("solo", solo, {"#/captures/0/annotations/1/values/0/labelId", "4294967298"});
  with("/captures/0/dimension/0", 1e300);
  ExpectRefused("solo", solo, {"#/captures/0/dimension/0"});
  WriteJson(step, original);

  // The camera image a link to a file outside: refused, or read with the flag.
  const fs::path png = solo / "sequence.0" / "step0.camera.png";
  ReplaceWithLink(png, OutsideCopyOf(png, dir_.path()));
  ExpectRefused("solo", solo, {"step0.frame_data.json#/captures/0/filename", "outside the source"});
  import::ImportOptions linked;
  linked.allow_links_outside = true;
  ExpectImports("solo", solo, linked);

  // Unity writes 0 for no surface; NaN is a broken file, not sky.
  const fs::path depth_file = solo / "sequence.0" / "step0.camera.Depth.exr";
  exr::FlatImage depth = exr::ReadFlatExr(depth_file);
  depth.Get("R").floats[depth.Index(3, 2)] = std::numeric_limits<float>::quiet_NaN();
  exr::WriteFlatExr(depth_file, depth);
  ExpectRefused("solo", solo, {"step0.camera.Depth.exr", "frame 0 pixel (3, 2)", "NaN"}, linked);
}

TEST_F(HostileImportTest, SoloSequenceNumbersBeyondInt64AreLocated) {
  const fs::path solo = dir_ / "solo";
  WriteSoloFixture(solo, spec_, 1);
  fs::rename(solo / "sequence.1", solo / "sequence.99999999999999999999");
  ExpectRefused("solo", solo, {"sequence.99999999999999999999", "beyond"});
}

TEST_F(HostileImportTest, AirSimImageNamesAndIds) {
  const fs::path rec = dir_ / "rec";
  WriteAirSimFixture(rec, spec_);
  const std::string text = ReadText(rec / "airsim_rec.txt");
  const size_t name = text.find("img_Drone1_");
  std::ofstream(rec / "airsim_rec.txt") << text.substr(0, name) + "../../" + text.substr(name);
  ExpectRefused("airsim", rec, {"airsim_rec.txt:2:", "leaves the source"});
  std::ofstream(rec / "airsim_rec.txt") << text;

  const json objects = ReadJson(rec / "lsds_objects.json");
  json broken = objects;
  broken["classes"][0]["id"] = 4294967298u;
  WriteJson(rec / "lsds_objects.json", broken);
  ExpectRefused("airsim", rec, {"lsds_objects.json#/classes/0/id", "4294967298"});
  broken = objects;
  broken["objects"][0]["instance_id"] = -1;
  WriteJson(rec / "lsds_objects.json", broken);
  ExpectRefused("airsim", rec, {"lsds_objects.json#/objects/0/instance_id", "-1"});
  WriteJson(rec / "lsds_objects.json", objects);

  // A link in images/ to a file outside the recording.
  const fs::path first = rec / "images" / text.substr(name, text.find(';', name) - name);
  ReplaceWithLink(first, OutsideCopyOf(first, dir_.path()));
  ExpectRefused("airsim", rec, {"airsim_rec.txt:2:", "outside the source"});
}

TEST_F(HostileImportTest, BopKeysAndModelIds) {
  const fs::path scene = WriteBopFixture(dir_ / "bop", spec_);
  const fs::path models_file = dir_ / "bop" / "models" / "models_info.json";
  const json models = ReadJson(models_file);
  json broken = models;
  broken["4294967297"] = broken["1"];
  WriteJson(models_file, broken);
  ExpectRefused("bop", scene, {"models_info.json#/4294967297", "not an obj_id"});
  WriteJson(models_file, models);

  const json cameras = ReadJson(scene / "scene_camera.json");
  broken = cameras;
  broken["99999999999999999999"] = broken["0"];
  WriteJson(scene / "scene_camera.json", broken);
  ExpectRefused("bop", scene, {"scene_camera.json#/99999999999999999999", "not an image id"});
  WriteJson(scene / "scene_camera.json", cameras);

  json gt = ReadJson(scene / "scene_gt.json");
  gt["0"][0]["obj_id"] = 4294967297u;
  WriteJson(scene / "scene_gt.json", gt);
  ExpectRefused("bop", scene, {"scene_gt.json#/0/0/obj_id", "4294967297"});
}

TEST_F(HostileImportTest, BopLinkedImagesAndModelsOutside) {
  const fs::path scene = WriteBopFixture(dir_ / "bop", spec_);
  const fs::path depth = scene / "depth" / "000000.png";
  ReplaceWithLink(depth, OutsideCopyOf(depth, dir_.path()));
  ExpectRefused("bop", scene, {"000000.png", "outside the source"});
}

TEST_F(HostileImportTest, KubricNanDepthAndLinks) {
  synth::Spec spec = spec_;
  spec.depth_kind = DepthKind::kPerspective;
  const fs::path scene = dir_ / "kubric";
  WriteKubricFixture(scene, spec);
  const fs::path metadata = scene / "metadata.json";
  ReplaceWithLink(metadata, OutsideCopyOf(metadata, dir_.path()));
  ExpectRefused("kubric", scene, {"metadata.json", "outside the source"});
  import::ImportOptions linked;
  linked.allow_links_outside = true;
  ExpectImports("kubric", scene, linked);

  const std::string tiff = (scene / "depth_00001.tiff").string();
  cv::Mat depth = cv::imread(tiff, cv::IMREAD_UNCHANGED);
  depth.at<float>(2, 3) = std::numeric_limits<float>::quiet_NaN();
  cv::imwrite(tiff, depth);
  ExpectRefused("kubric", scene, {"depth_00001.tiff", "frame 1 pixel (3, 2)", "NaN"}, linked);
}

TEST_F(HostileImportTest, ReplicatorPrimPathsColourKeysAndFrameNumbers) {
  const fs::path folder = dir_ / "replicator";
  WriteReplicatorFixture(folder, spec_);
  const fs::path mapping_file = folder / "instance_segmentation_mapping_0000.json";
  const json mapping = ReadJson(mapping_file);
  json broken = mapping;
  const std::string key = mapping.items().begin().key();
  broken[key] = json::array({1, 2});
  WriteJson(mapping_file, broken);
  ExpectRefused("replicator",
                folder,
                {"instance_segmentation_mapping_0000.json#/" + key, "expected a string"});

  broken = mapping;
  broken["(99999999999, 0, 0, 255)"] = "BACKGROUND";
  WriteJson(mapping_file, broken);
  ExpectRefused("replicator", folder, {"#/(99999999999, 0, 0, 255)", "colour key"});
  WriteJson(mapping_file, mapping);

  const fs::path paths_file = folder / "bounding_box_3d_prim_paths_0000.json";
  json paths = ReadJson(paths_file);
  paths[0] = nullptr;
  WriteJson(paths_file, paths);
  ExpectRefused("replicator", folder, {"bounding_box_3d_prim_paths_0000.json#/0", "string"});
  fs::remove_all(folder);

  WriteReplicatorFixture(folder, spec_);
  fs::copy_file(folder / "rgb_0000.png", folder / "rgb_99999999999999999999.png");
  ExpectRefused("replicator", folder, {"rgb_99999999999999999999.png", "beyond"});
}

TEST_F(HostileImportTest, UeMrqIdsAndLinkedFrames) {
  const fs::path shot = dir_ / "shot";
  WriteMrqFixture(shot, spec_);
  const fs::path sidecar = shot / "lsds_objects.json";
  const json objects = ReadJson(sidecar);
  json broken = objects;
  broken["classes"][0]["id"] = 4294967298u;
  WriteJson(sidecar, broken);
  ExpectRefused("ue-mrq", shot, {"lsds_objects.json#/classes/0/id", "4294967298"});
  broken = objects;
  broken["actors"][0]["instance_id"] = -1;
  WriteJson(sidecar, broken);
  ExpectRefused("ue-mrq", shot, {"lsds_objects.json#/actors/0/instance_id", "-1"});
  broken = objects;
  broken["actors"][0]["name"] = json::object();
  WriteJson(sidecar, broken);
  ExpectRefused("ue-mrq", shot, {"lsds_objects.json#/actors/0/name", "expected a string"});
  WriteJson(sidecar, objects);

  const fs::path frame = shot / "Shot.0001.exr";
  ReplaceWithLink(frame, OutsideCopyOf(frame, dir_.path()));
  ExpectRefused("ue-mrq", shot, {"Shot.0001.exr", "outside the source"});
}

// The CLI: the flag, exit 2, the message naming the place.
TEST_F(HostileImportTest, TheCommandLineSaysWhereAndExitsTwo) {
  const fs::path scene = dir_ / "kubric";
  synth::Spec spec = spec_;
  spec.depth_kind = DepthKind::kPerspective;
  WriteKubricFixture(scene, spec);
  const fs::path rgb = scene / "rgba_00000.png";
  ReplaceWithLink(rgb, OutsideCopyOf(rgb, dir_.path()));
  const std::string command =
      LsdsBinary() + " import kubric " + scene.string() + " -o " + (dir_ / "out").string();
  CommandResult result = RunCommandLine(command);
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("rgba_00000.png"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("--allow-links-outside"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  result = RunCommandLine(command + " --allow-links-outside");
  EXPECT_EQ(result.exit_code, 0) << result.output;
}

}  // namespace
}  // namespace lsds::testing
