// End to end, the way a user meets them: full disks, wrong-size layers,
// leftovers of killed runs, malformed numbers, text and file references.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "synth/synthetic_collection.h"
#include "tests/build_paths.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::RunCommandLine;

std::string Lsds() { return testing::LsdsBinary(); }

std::string Q(const fs::path& path) { return "'" + path.string() + "'"; }

// A small synthetic collection (4 frames of 32x24, every layer).
fs::path MakeCollection(const testing::TempDir& dir, const std::string& name = "c") {
  synth::Spec spec = synth::DefaultSpec();
  spec.width = 32;
  spec.height = 24;
  synth::WriteCollection(dir / name, spec);
  return dir / name;
}

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Every file name under `root` (recursively) that is a temporary of the
// atomic-output path.
std::vector<std::string> Temporaries(const fs::path& root) {
  std::vector<std::string> found;
  if (!fs::exists(root)) return found;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    if (IsTempName(entry.path().filename().string())) found.push_back(entry.path().string());
  return found;
}

// ---- full disk ----

TEST(FullDisk, InjectedWriteFailureLeavesNothingUnderTheFinalName) {
  testing::TempDir dir;
  const fs::path c = MakeCollection(dir);
  const fs::path out = dir / "out";
  fs::create_directory(out);
  // Fused cloud: the issue's case (a truncated PLY under its final name).
  const CommandResult fused =
      RunCommandLine("LSDS_FAULT_WRITE_BYTES=2000 " + Lsds() + " backproject --fuse -o " +
                     Q(out / "cloud.ply") + " " + Q(c));
  EXPECT_NE(fused.exit_code, 0) << fused.output;
  EXPECT_NE(fused.output.find("No space left on device"), std::string::npos) << fused.output;
  EXPECT_NE(fused.output.find("cloud.ply"), std::string::npos) << fused.output;
  EXPECT_FALSE(fs::exists(out / "cloud.ply"));
  EXPECT_TRUE(fs::is_empty(out)) << "leftovers in " << out;
  // The same command with room to write succeeds: the failure was the disk.
  const CommandResult ok =
      RunCommandLine(Lsds() + " backproject --fuse -o " + Q(out / "cloud.ply") + " " + Q(c));
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_GT(fs::file_size(out / "cloud.ply"), 2000u);

  // A converter (a folder of files) and a report (one file).
  for (const std::string& command : {"convert --to coco,yolo -o " + Q(dir / "conv") + " " + Q(c),
                                     "report -o " + Q(dir / "report.html") + " " + Q(c),
                                     "bundles --write-layers majority " + Q(c)}) {
    const CommandResult failed =
        RunCommandLine("LSDS_FAULT_WRITE_BYTES=3000 " + Lsds() + " " + command);
    EXPECT_NE(failed.exit_code, 0) << command << "\n" << failed.output;
    EXPECT_NE(failed.output.find("No space left on device"), std::string::npos) << command << "\n"
                                                                                << failed.output;
  }
  EXPECT_FALSE(fs::exists(dir / "conv"));
  EXPECT_FALSE(fs::exists(dir / "report.html"));
  EXPECT_TRUE(Temporaries(dir.path()).empty());
}

// A real full file system: a 256 KiB tmpfs in a user and mount namespace.
// Skipped where the system does not allow unprivileged namespaces.
TEST(FullDisk, SmallTmpfs) {
  testing::TempDir dir;
  const fs::path c = MakeCollection(dir);
  const fs::path mount = dir / "small";
  fs::create_directory(mount);
  const std::string probe =
      "unshare -r -m sh -c 'mount -t tmpfs -o size=256k "
      "tmpfs " +
      Q(mount).substr(1, Q(mount).size() - 2) + "' >/dev/null 2>&1";
  if (RunCommandLine(probe).exit_code != 0)
    GTEST_SKIP() << "unprivileged tmpfs mounts are not permitted here";
  // 4 frames of every layer back-projected at full density: about 100 KiB
  // per frame as PLY; fused, several times the 256 KiB.
  const std::string script = "mount -t tmpfs -o size=256k tmpfs " + mount.string() + " && " +
                             "dd if=/dev/zero of=" + mount.string() + "/fill bs=1k count=200 " +
                             "2>/dev/null; " + Lsds() + " backproject --fuse -o " + mount.string() +
                             "/cloud.ply " + c.string() + "; echo exit=\\$?; ls -a " +
                             mount.string();
  const CommandResult result = RunCommandLine("unshare -r -m sh -c \"" + script + "\"");
  EXPECT_EQ(result.output.find("exit=0"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("exit="), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("cloud.ply"), result.output.rfind("cloud.ply"))
      << "the listing must not show cloud.ply\n"
      << result.output;
  EXPECT_EQ(result.output.find("lsds-tmp"), std::string::npos) << result.output;
}

// ---- wrong-size layers ----

TEST(LayerSize, WrongSizeLayerIsAnErrorNamingFrameAndLayer) {
  testing::TempDir dir;
  const fs::path c = MakeCollection(dir);
  const nlohmann::json collection = ReadJson(c / "collection.json");
  const std::string ids_file = collection["frames"][1]["files"]["instanceid"].get<std::string>();
  const std::string rgb_file = collection["frames"][1]["files"]["rgb"].get<std::string>();
  // 8x6 layers where the camera says 32x24.
  exr::FlatImage ids(8, 6);
  ids.AddChannel("id", exr::PixelType::kUint);
  exr::WriteFlatExr(c / ids_file, ids);
  exr::FlatImage rgb(8, 6);
  for (const char* channel : {"R", "G", "B"}) rgb.AddChannel(channel, exr::PixelType::kHalf);
  exr::WriteFlatExr(c / rgb_file, rgb);
  const std::vector<std::string> commands = {
      "convert --to yolo -o " + Q(dir / "y") + " " + Q(c),
      "convert --to coco --images none -o " + Q(dir / "k") + " " + Q(c),
  };
  for (const std::string& command : commands) {
    const CommandResult result = RunCommandLine(Lsds() + " " + command);
    EXPECT_TRUE(result.exit_code == 1 || result.exit_code == 2) << command << "\n" << result.output;
    EXPECT_NE(result.output.find("frame 1"), std::string::npos) << command << "\n" << result.output;
    EXPECT_NE(result.output.find("is 8x6 but the frame's camera is 32x24"), std::string::npos)
        << command << "\n"
        << result.output;
  }
  EXPECT_FALSE(fs::exists(dir / "y"));
  EXPECT_FALSE(fs::exists(dir / "k"));
  // The report is a view of the data: it shows the frame's failure in the
  // page (and never draws the wrong-size layer) instead of stopping.
  const CommandResult report =
      RunCommandLine(Lsds() + " report -o " + Q(dir / "r.html") + " " + Q(c));
  ASSERT_EQ(report.exit_code, 0) << report.output;
  const std::string page = ReadText(dir / "r.html");
  EXPECT_NE(page.find("is 8x6 but the frame"), std::string::npos);
  EXPECT_NE(page.find("frame 1"), std::string::npos);
}

TEST(LayerSize, BundlesAndBackprojectCheckToo) {
  testing::TempDir dir;
  const fs::path c = MakeCollection(dir);
  const nlohmann::json collection = ReadJson(c / "collection.json");
  // A depth layer of the wrong size.
  const std::string depth_file = collection["frames"][2]["files"]["depth"].get<std::string>();
  exr::FlatImage depth(16, 12);
  depth.AddChannel("Z", exr::PixelType::kFloat);
  exr::WriteFlatExr(c / depth_file, depth);
  const CommandResult back =
      RunCommandLine(Lsds() + " backproject -o " + Q(dir / "clouds") + " " + Q(c));
  EXPECT_TRUE(back.exit_code == 1 || back.exit_code == 2) << back.output;
  EXPECT_NE(back.output.find("frame 2"), std::string::npos) << back.output;
  EXPECT_NE(back.output.find("layer 'depth'"), std::string::npos) << back.output;
  // A bundle layer from another frame size.
  const fs::path small = [&] {
    synth::Spec spec = synth::DefaultSpec();
    spec.width = 16;
    spec.height = 12;
    synth::WriteCollection(dir / "small", spec);
    return dir / "small";
  }();
  const std::string bundle_file = collection["frames"][0]["files"]["bundle"].get<std::string>();
  fs::copy_file(small / bundle_file, c / bundle_file, fs::copy_options::overwrite_existing);
  const CommandResult bundles =
      RunCommandLine(Lsds() + " bundles --write-layers majority --force " + Q(c));
  EXPECT_TRUE(bundles.exit_code == 1 || bundles.exit_code == 2) << bundles.output;
  EXPECT_NE(bundles.output.find("frame 0"), std::string::npos) << bundles.output;
  EXPECT_NE(bundles.output.find("layer 'bundle' is 16x12"), std::string::npos) << bundles.output;
}

// ---- leftovers of killed runs ----

TEST(Leftovers, ResumeRemovesTemporariesOfAKilledRunAndNeverCountsThem) {
  testing::TempDir dir;
  const fs::path out = dir / "gen";
  const std::string generate = Lsds() +
                               " generate --demo --demo-frames 2 "
                               "--demo-size 24x16 --spp 1 -q -o " +
                               Q(out);
  ASSERT_EQ(RunCommandLine(generate).exit_code, 0);
  // A killed run's leftovers: temporaries of a process that is gone, one in
  // a layer folder and one beside collection.json.
  const std::string own = TempPathBeside(out / "rgb" / "000000.exr").filename().string();
  const size_t last = own.rfind('-'), before = own.rfind('-', last - 1);
  const std::string dead_suffix = "2147483646" + own.substr(last);
  const fs::path left1 = out / "rgb" / (own.substr(0, before + 1) + dead_suffix);
  const std::string own2 = TempPathBeside(out / "collection.json").filename().string();
  const size_t before2 = own2.rfind('-', own2.rfind('-') - 1);
  const fs::path left2 = out / (own2.substr(0, before2 + 1) + dead_suffix);
  WriteText(left1, "half an EXR");
  WriteText(left2, "{\"frames\": [");
  // The user also deletes one frame's rgb file: --resume renders it again.
  const nlohmann::json before_json = ReadJson(out / "collection.json");
  fs::remove(out / before_json["frames"][1]["files"]["rgb"].get<std::string>());
  const CommandResult resumed =
      RunCommandLine(Lsds() +
                     " generate --demo --demo-frames 2 --demo-size 24x16 --spp 1 "
                     "--resume -o " +
                     Q(out));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_FALSE(fs::exists(left1));
  EXPECT_FALSE(fs::exists(left2));
  EXPECT_TRUE(Temporaries(out).empty());
  const nlohmann::json after = ReadJson(out / "collection.json");
  EXPECT_EQ(after["frame_count"], 2);
  EXPECT_EQ(after["frames"].size(), 2u);
  for (const auto& frame : after["frames"])
    for (const auto& [layer, file] : frame["files"].items())
      EXPECT_FALSE(IsTempName(fs::path(file.get<std::string>()).filename())) << file;
  const CommandResult valid = RunCommandLine(Lsds() + " validate " + Q(out));
  EXPECT_EQ(valid.exit_code, 0) << valid.output;
}

TEST(Leftovers, AFailedResumeDoesNotLeaveTheFolderPresentedAsComplete) {
  testing::TempDir dir;
  const fs::path out = dir / "gen";
  const std::string generate = Lsds() +
                               " generate --demo --demo-frames 2 "
                               "--demo-size 24x16 --spp 1 -q -o " +
                               Q(out);
  ASSERT_EQ(RunCommandLine(generate).exit_code, 0);
  const nlohmann::json before = ReadJson(out / "collection.json");
  fs::remove(out / before["frames"][0]["files"]["rgb"].get<std::string>());
  // The disk fills while the missing frame is rendered again.
  const CommandResult failed =
      RunCommandLine("LSDS_FAULT_WRITE_BYTES=500 " + generate + " --resume");
  EXPECT_NE(failed.exit_code, 0) << failed.output;
  EXPECT_FALSE(fs::exists(out / "collection.json"))
      << "a failed run must not leave a collection.json";
  const CommandResult info = RunCommandLine(Lsds() + " validate " + Q(out));
  EXPECT_NE(info.exit_code, 0) << info.output;
  EXPECT_TRUE(Temporaries(out).empty());
  // Resuming again finishes it.
  const CommandResult resumed = RunCommandLine(generate + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(RunCommandLine(Lsds() + " validate " + Q(out)).exit_code, 0);
}

// Every file under `root` that is not a temporary, with a hash of its bytes
// (a failure then lists names, not EXR bytes).
std::map<std::string, size_t> FilesWithoutTemporaries(const fs::path& root) {
  std::map<std::string, size_t> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string rel = fs::relative(entry.path(), root).string();
    if (rel.find(".lsds-tmp-") != std::string::npos) continue;
    files[rel] = entry.is_directory() ? 0 : std::hash<std::string>()(ReadText(entry.path()));
  }
  return files;
}

// The instant collection.json appears is the one a kill can split: before
// it the folder is an interrupted run, after it a finished collection, and
// never a finished collection that still holds the work folder.
TEST(Leftovers, AKillAsTheCollectionIsAssembledLeavesItFinishedOrResumable) {
  testing::TempDir dir;
  const std::string generate = Lsds() +
                               " generate --demo --demo-frames 2 "
                               "--demo-size 24x16 --spp 4 -q -o ";
  ASSERT_EQ(RunCommandLine(generate + Q(dir / "reference")).exit_code, 0);
  const auto reference = FilesWithoutTemporaries(dir / "reference");

  // Killed right after collection.json appears: finished, and the same as a
  // run that was not killed; the retired work folder is only a temporary.
  const fs::path after = dir / "after";
  EXPECT_NE(
      RunCommandLine("LSDS_FAULT_KILL_AFTER=collection.json " + generate + Q(after)).exit_code, 0);
  ASSERT_TRUE(fs::exists(after / "collection.json"));
  EXPECT_FALSE(fs::exists(after / ".lsds-generate"));
  EXPECT_FALSE(Temporaries(after).empty()) << "the kill came before the work folder was removed";
  EXPECT_EQ(FilesWithoutTemporaries(after), reference);
  const CommandResult valid = RunCommandLine(Lsds() + " validate --fail-on warning " + Q(after));
  EXPECT_EQ(valid.exit_code, 0) << valid.output;

  // Killed just before (metadata.json is committed right before it): not a
  // collection, and --resume finishes it byte for byte.
  const fs::path before = dir / "before";
  EXPECT_NE(RunCommandLine("LSDS_FAULT_KILL_AFTER=metadata.json " + generate + Q(before)).exit_code,
            0);
  EXPECT_FALSE(fs::exists(before / "collection.json"));
  EXPECT_NE(RunCommandLine(Lsds() + " validate " + Q(before)).exit_code, 0);
  const CommandResult resumed = RunCommandLine(generate + Q(before) + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(Temporaries(before).empty());
  EXPECT_EQ(FilesWithoutTemporaries(before), reference);
}

// ---- numbers ----

// Writes collection.json with `edit` applied to its text.
void EditCollection(const fs::path& c, const std::function<std::string(std::string)>& edit) {
  WriteText(c / "collection.json", edit(ReadText(c / "collection.json")));
}

std::string ReplaceFirst(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(Numbers, MalformedNumbersInCollectionJsonAreLocated) {
  struct Case {
    std::string from, to, expect;
  };
  const std::vector<Case> cases = {
      {"\"width\":32", "\"width\":4294967297", "4294967297"},
      {"\"fx\":", "\"fx\":1e999,\"x\":", "1e999"},
      {"\"instance_id\":", "\"instance_id\":-1,\"x\":", "instance_id"},
  };
  for (const Case& c : cases) {
    testing::TempDir dir;
    const fs::path root = MakeCollection(dir);
    // collection.json is written one frame per line without spaces.
    EditCollection(root, [&](std::string text) { return ReplaceFirst(text, c.from, c.to); });
    for (const char* command : {"info", "validate"}) {
      const CommandResult result = RunCommandLine(Lsds() + " " + command + " " + Q(root));
      EXPECT_TRUE(result.exit_code == 1 || result.exit_code == 2) << c.to << "\n" << result.output;
      EXPECT_NE(result.output.find("collection.json"), std::string::npos) << result.output;
      EXPECT_NE(result.output.find(c.expect), std::string::npos) << result.output;
      // Located: a line:column or a JSON pointer.
      EXPECT_TRUE(
          std::regex_search(result.output, std::regex("collection\\.json(:[0-9]+:[0-9]+|#/)")))
          << result.output;
    }
  }
}

TEST(Numbers, NulByteEndsNothing) {
  testing::TempDir dir;
  const fs::path root = MakeCollection(dir);
  EditCollection(root, [](std::string text) {
    // After the first frame: a NUL, then the rest of the document.
    const size_t at = text.find("\n", text.find("\"frames\""));
    return text.substr(0, at) + std::string(1, '\0') + text.substr(at);
  });
  const CommandResult result = RunCommandLine(Lsds() + " info " + Q(root));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(std::regex_search(result.output, std::regex("collection\\.json:[0-9]+:[0-9]+")))
      << result.output;
}

TEST(Numbers, FlagsAreRangeChecked) {
  testing::TempDir dir;
  const fs::path c = MakeCollection(dir);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"backproject --fuse --voxel nan -o " + Q(dir / "a.ply") + " " + Q(c), "--voxel"},
      {"backproject --fuse --voxel 1e999 -o " + Q(dir / "a.ply") + " " + Q(c), "--voxel"},
      {"backproject --check --tolerance NaN -o " + Q(dir / "b") + " " + Q(c), "--tolerance"},
      {"perturb-metadata --model gaussian --sigma 1 --seed -1 -o " + Q(dir / "m.json") + " " + Q(c),
       "--seed"},
      {"generate --demo --seed -1 -o " + Q(dir / "g"), "--seed"},
  };
  for (const auto& [command, flag] : cases) {
    const CommandResult result = RunCommandLine(Lsds() + " " + command);
    EXPECT_EQ(result.exit_code, 2) << command << "\n" << result.output;
    EXPECT_NE(result.output.find(flag), std::string::npos) << command << "\n" << result.output;
  }
  EXPECT_FALSE(fs::exists(dir / "a.ply"));
  EXPECT_FALSE(fs::exists(dir / "g"));
}

// ---- text ----

TEST(Text, Latin1ByteInAnLsceneCommentIsLocated) {
  testing::TempDir dir;
  const fs::path examples = ::lsds::testing::ExamplesDir();
  std::string scene = ReadText(examples / "uav_survey.lscene");
  // Line 1 is a comment: put a Latin-1 'é' (0xE9) at its column 5.
  scene = scene.substr(0, 4) + "\xE9" + scene.substr(4);
  WriteText(dir / "s.lscene", scene);
  const CommandResult result =
      RunCommandLine(Lsds() + " plan " + Q(dir / "s.lscene") + " " +
                     Q(examples / "uav_survey.lcap") + " -o " + Q(dir / "plan.json"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("s.lscene:1:5"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("UTF-8"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("type_error"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir / "plan.json"));
}

TEST(Text, NonUtf8FolderNameIsCarriedEscaped) {
  testing::TempDir dir;
  const fs::path c = MakeCollection(dir, "caf\xE9");
  const CommandResult info = RunCommandLine(Lsds() + " info --json " + Q(c));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const nlohmann::json summary = nlohmann::json::parse(info.output);
  EXPECT_NE(summary["path"].get<std::string>().find("caf\\xE9"), std::string::npos);
  const CommandResult bundles =
      RunCommandLine(Lsds() + " bundles -o " + Q(dir / "stats.json") + " " + Q(c));
  ASSERT_EQ(bundles.exit_code, 0) << bundles.output;
  EXPECT_NE(ReadText(dir / "stats.json").find("caf\\\\xE9"), std::string::npos);
  const CommandResult validate = RunCommandLine(Lsds() + " validate --format json " + Q(c));
  EXPECT_EQ(validate.output.find("type_error"), std::string::npos) << validate.output;
}

TEST(Text, PerturbMetadataErrorsCarryLineColumnAndAnExcerpt) {
  testing::TempDir dir;
  const fs::path c = MakeCollection(dir);
  std::string metadata = ReadText(c / "metadata.json");
  // Break the third frame's element.
  size_t at = metadata.find("\"frames\"");
  for (int k = 0; k < 3; ++k) at = metadata.find("\n", at + 1);
  const size_t line_start = at + 1;
  const size_t brace = metadata.find('{', line_start);
  metadata.insert(brace + 1, "\"index\": 2,, ");
  WriteText(c / "metadata.json", metadata);
  int line = 1;
  for (size_t i = 0; i < line_start; ++i) line += metadata[i] == '\n';
  const CommandResult result =
      RunCommandLine(Lsds() + " perturb-metadata --model gaussian --sigma 1 --seed 1 -o " +
                     Q(dir / "m.json") + " " + Q(c));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("metadata.json:" + std::to_string(line) + ":"), std::string::npos)
      << "line " << line << "\n"
      << result.output;
  EXPECT_NE(result.output.find("near '"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("\"index\": 2,,"), std::string::npos) << result.output;
}

TEST(Text, PlanErrorsAndMessagesAreReadable) {
  testing::TempDir dir;
  // generate --plan: a syntax error at line:column.
  WriteText(dir / "plan.json", "{\n  \"seed\": 1,\n  \"frames\": [}\n");
  const CommandResult plan =
      RunCommandLine(Lsds() + " generate --plan " + Q(dir / "plan.json") + " -o " + Q(dir / "out"));
  EXPECT_EQ(plan.exit_code, 2) << plan.output;
  EXPECT_NE(plan.output.find("plan.json:3:14"), std::string::npos) << plan.output;
  // `lsds plan DIR`: says that it is a folder.
  const CommandResult folder =
      RunCommandLine(Lsds() + " plan " + Q(dir.path()) + " -o " + Q(dir / "p.json"));
  EXPECT_EQ(folder.exit_code, 2) << folder.output;
  EXPECT_NE(folder.output.find("is a folder"), std::string::npos) << folder.output;
  // A 10 MB identifier gives a short message.
  const fs::path examples = ::lsds::testing::ExamplesDir();
  std::string scene = ReadText(examples / "uav_survey.lscene");
  scene += "\n" + std::string(10 << 20, 'Q') + " = box{size:[1,1,1]}\n";
  WriteText(dir / "big.lscene", scene);
  const CommandResult big =
      RunCommandLine(Lsds() + " plan " + Q(dir / "big.lscene") + " " +
                     Q(examples / "uav_survey.lcap") + " -o " + Q(dir / "q.json"));
  EXPECT_NE(big.exit_code, 0);
  EXPECT_LT(big.output.size(), 5000u) << big.output.substr(0, 500);
}

// ---- paths ----

TEST(Paths, FileReferencesStayInsideTheCollection) {
  for (const std::string& reference : {std::string("../outside.exr"),
                                       std::string("/etc/passwd"),
                                       std::string("rgb/../../x.exr")}) {
    testing::TempDir dir;
    const fs::path c = MakeCollection(dir);
    WriteText(dir / "outside.exr", "not ours");
    nlohmann::json collection = ReadJson(c / "collection.json");
    collection["frames"][1]["files"]["rgb"] = reference;
    WriteText(c / "collection.json", collection.dump());
    for (const std::string& command : {"info " + Q(c),
                                       "validate " + Q(c),
                                       "convert --to yolo -o " + Q(dir / "y") + " " + Q(c)}) {
      const CommandResult result = RunCommandLine(Lsds() + " " + command);
      EXPECT_TRUE(result.exit_code == 1 || result.exit_code == 2) << command << "\n"
                                                                  << result.output;
      EXPECT_NE(result.output.find("#/frames/1/files/rgb"), std::string::npos) << command << "\n"
                                                                               << result.output;
    }
  }
  // A metadata variant outside.
  testing::TempDir dir;
  const fs::path c = MakeCollection(dir);
  nlohmann::json collection = ReadJson(c / "collection.json");
  collection["metadata"][0]["file"] = "../m.json";
  WriteText(c / "collection.json", collection.dump());
  const CommandResult result = RunCommandLine(Lsds() + " info " + Q(c));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("#/metadata/0/file"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace lsds
