// The CLI table test of docs/cli.md: every command lists the common flags in
// its help and refuses those it has no use for; every command that takes --frames accepts
// the same forms with the same meaning (checked on the frames each command
// actually produced), an out-of-range --frames is exit 2 naming the valid
// range and leaves an existing output alone, and the same bad flag gives the
// same error form with a suggestion in every command.
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "converters/registry.h"
#include "importers/registry.h"
#include "synth/synthetic_collection.h"
#include "tests/build_paths.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::RunCommandLine;

const std::string kExamples = ::lsds::testing::ExamplesDir();

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::set<int64_t> FrameIndices(const nlohmann::json& frames) {
  std::set<int64_t> indices;
  for (const auto& frame : frames) indices.insert(frame["index"].get<int64_t>());
  return indices;
}

std::set<int64_t> FileStems(const fs::path& folder) {
  std::set<int64_t> stems;
  for (const auto& entry : fs::directory_iterator(folder))
    stems.insert(std::stoll(entry.path().stem().string()));
  return stems;
}

// One command of the table: the command line for a --frames value and an
// output folder, and the frame indices the output holds.
struct FramesCommand {
  std::string name;
  std::function<std::string(const fs::path& out)> command_line;
  std::function<std::set<int64_t>(const fs::path& out)> produced;
  int64_t first_frame_of_input;  // the input's frames are first.. first+3 at least
};

class CliGrammar : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir();
    synth::Spec spec = synth::DefaultSpec();  // frames 0..3
    spec.width = 32, spec.height = 24;
    synth::WriteCollection(*dir_ / "c", spec);
  }
  static void TearDownTestSuite() { delete dir_; }

  static std::string Lsds() { return testing::LsdsBinary(); }
  static std::string C() { return (*dir_ / "c").string(); }

  static std::vector<FramesCommand> Table() {
    const std::string scene = kExamples + "/uav_survey.lscene ";
    const std::string capture = kExamples + "/uav_survey.lcap ";
    return {
        {"plan",
         [=](const fs::path& out) {
           return Lsds() + " plan " + scene + capture + "-o " + (out / "plan.json").string();
         },
         [](const fs::path& out) { return FrameIndices(ReadJson(out / "plan.json")["frames"]); },
         0},
        {"generate",
         [](const fs::path& out) {
           return Lsds() +
                  " generate --demo --demo-frames 4 --demo-size 16x16 --spp 1 "
                  "-q -o " +
                  (out / "g").string();
         },
         [](const fs::path& out) {
           return FrameIndices(ReadJson(out / "g" / "collection.json")["frames"]);
         },
         0},
        {"convert",
         [](const fs::path& out) {
           return Lsds() + " convert " + C() + " --to coco --images none -q -o " +
                  (out / "coco").string();
         },
         [](const fs::path& out) {
           std::set<int64_t> ids;
           for (const auto& entry : fs::recursive_directory_iterator(out / "coco")) {
             if (entry.path().extension() != ".json" ||
                 entry.path().filename() == "loss_report.json")
               continue;
             const nlohmann::json coco = ReadJson(entry.path());
             if (!coco.contains("images")) continue;
             for (const auto& image : coco["images"]) {
               const std::string name = image["file_name"];
               ids.insert(std::stoll(fs::path(name).stem().string()));
             }
           }
           return ids;
         },
         0},
        {"bundles",
         [](const fs::path& out) {
           return Lsds() + " bundles " + C() + " -o " + (out / "stats.json").string();
         },
         [](const fs::path& out) { return FrameIndices(ReadJson(out / "stats.json")["frames"]); },
         0},
        {"backproject",
         [](const fs::path& out) {
           return Lsds() + " backproject " + C() + " -o " + (out / "clouds").string();
         },
         [](const fs::path& out) { return FileStems(out / "clouds"); },
         0},
        {"export-layers",
         [](const fs::path& out) {
           return Lsds() + " export-layers " + C() + " --layers depth -o " +
                  (out / "layers").string();
         },
         [](const fs::path& out) { return FileStems(out / "layers" / "depth"); },
         0},
    };
  }

  static testing::TempDir* dir_;
};

testing::TempDir* CliGrammar::dir_ = nullptr;

TEST_F(CliGrammar, EveryCommandReadsTheFramesFormsTheSameWay) {
  const std::vector<std::pair<std::string, std::set<int64_t>>> forms = {
      {"1:3", {1, 2}}, {"2:", {2, 3}}, {":2", {0, 1}}, {"2", {2}}};
  for (const FramesCommand& command : Table()) {
    for (const auto& [text, expected] : forms) {
      testing::TempDir out;
      const CommandResult result =
          RunCommandLine(command.command_line(out.path()) + " --frames " + text);
      ASSERT_EQ(result.exit_code, 0) << command.name << " --frames " << text << "\n"
                                     << result.output;
      std::set<int64_t> got = command.produced(out.path());
      if (command.name == "plan" && text == "2:") {
        // The plan has more than 4 frames: 2: runs to its last one.
        ASSERT_FALSE(got.empty());
        EXPECT_EQ(*got.begin(), 2);
        EXPECT_EQ(static_cast<int64_t>(got.size()), *got.rbegin() - 1);
        EXPECT_GT(got.size(), 2u);
        continue;
      }
      EXPECT_EQ(got, expected) << command.name << " --frames " << text;
    }
  }
}

TEST_F(CliGrammar, OutOfRangeFramesAreExit2NamingTheRangeAndKeepTheOutput) {
  for (const FramesCommand& command : Table()) {
    for (const std::string text : {"100", "100:200", "2:100"}) {
      testing::TempDir out;
      // An existing output that --force must not wipe for a bad selection.
      fs::create_directories(out / "g");
      fs::create_directories(out / "coco");
      fs::create_directories(out / "clouds");
      std::ofstream(out / "keep.txt") << "keep";
      const CommandResult result =
          RunCommandLine(command.command_line(out.path()) + " --frames " + text + " --force");
      EXPECT_EQ(result.exit_code, 2) << command.name << " " << result.output;
      EXPECT_EQ(result.output.rfind(
                    "lsds " + command.name + ": error: --frames " + text + ": out of range: ", 0),
                0u)
          << result.output;
      EXPECT_NE(result.output.find("frame indices 0 to "), std::string::npos) << result.output;
      EXPECT_TRUE(fs::exists(out / "keep.txt"));
      EXPECT_FALSE(fs::exists(out / "plan.json"));
      EXPECT_FALSE(fs::exists(out / "stats.json"));
      EXPECT_TRUE(fs::is_empty(out / "g")) << command.name;
      EXPECT_TRUE(fs::is_empty(out / "clouds")) << command.name;
    }
  }
}

TEST_F(CliGrammar, BadFramesTextIsTheSameErrorEverywhere) {
  for (const FramesCommand& command : Table()) {
    testing::TempDir out;
    const CommandResult result = RunCommandLine(command.command_line(out.path()) + " --frames 3:1");
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_EQ(result.output.rfind(
                  "lsds " + command.name + ": error: --frames 3:1: the range is empty", 0),
              0u)
        << result.output;
  }
}

TEST_F(CliGrammar, SynthTakesACountAndExplainsFrames) {
  testing::TempDir out;
  const CommandResult count =
      RunCommandLine(Lsds() + " synth " + (out / "s").string() + " --count 2 --size 16x12");
  ASSERT_EQ(count.exit_code, 0) << count.output;
  EXPECT_EQ(ReadJson(out / "s" / "collection.json")["frames"].size(), 2u);
  const CommandResult frames =
      RunCommandLine(Lsds() + " synth " + (out / "t").string() + " --frames 2");
  EXPECT_EQ(frames.exit_code, 2);
  EXPECT_EQ(frames.output.rfind("lsds synth: error: --frames 2: ", 0), 0u) << frames.output;
  EXPECT_NE(frames.output.find("--count N"), std::string::npos);
  EXPECT_FALSE(fs::exists(out / "t"));
}

// The same mistyped flag, the same message form and suggestion, in every
// command; the positional arguments are valid so the flag is the only fault.
TEST_F(CliGrammar, AMistypedFlagGetsTheDocumentedErrorWithASuggestion) {
  const std::string scene = kExamples + "/uav_survey.lscene";
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"generate", "--demo -o /nonexistent/x"},
      {"plan", scene},
      {"info", C()},
      {"validate", C()},
      {"convert", C() + " --to coco -o /nonexistent/x"},
      {"perturb-metadata", C() + " --seed 1"},
      {"bundles", C()},
      {"backproject", C()},
      {"export-layers", C() + " -o /nonexistent/x"},
      {"synth", "/nonexistent/x"},
  };
  for (const auto& [name, args] : commands) {
    const CommandResult result = RunCommandLine(Lsds() + " " + name + " " + args + " --hepl");
    EXPECT_EQ(result.exit_code, 2) << name;
    EXPECT_EQ(result.output,
              "lsds " + name +
                  ": error: unknown option '--hepl' (did you mean '--help'?); "
                  "run 'lsds " +
                  name + " --help' for the options\n");
  }
  // Command-specific options are suggested the same way.
  for (const std::string name :
       {"generate", "convert", "bundles", "backproject", "validate", "synth"}) {
    const std::string args = name == "generate"  ? "--demo -o /nonexistent/x"
                             : name == "convert" ? C() + " --to coco -o /nonexistent/x"
                             : name == "synth"   ? "/nonexistent/x"
                                                 : C();
    const CommandResult result = RunCommandLine(Lsds() + " " + name + " " + args + " --thraeds=2");
    EXPECT_EQ(result.exit_code, 2) << name;
    EXPECT_NE(result.output.find("lsds " + name +
                                 ": error: unknown option '--thraeds' (did "
                                 "you mean '--threads'?)"),
              std::string::npos)
        << result.output;
  }
  const CommandResult frames = RunCommandLine(Lsds() + " backproject " + C() + " --frmaes 1");
  EXPECT_NE(frames.output.find("(did you mean '--frames'?)"), std::string::npos) << frames.output;
}

TEST_F(CliGrammar, ValidateChecksExcludeAndRejectUnknownNames) {
  testing::TempDir out;
  const auto run = [&](const std::string& checks) {
    return RunCommandLine(Lsds() + " validate " + C() + " --format json --checks " + checks);
  };
  auto ids = [](const std::string& json_text) {
    std::set<std::string> ids;
    const nlohmann::json report = nlohmann::json::parse(json_text);
    for (const auto& check : report["checks"]) ids.insert(check["id"].get<std::string>());
    return ids;
  };
  const CommandResult all = run("all");
  ASSERT_EQ(all.exit_code, 0) << all.output;
  const CommandResult no_camera = run("all,-camera");
  ASSERT_EQ(no_camera.exit_code, 0) << no_camera.output;
  const CommandResult minus_camera = run("-camera");
  ASSERT_EQ(minus_camera.exit_code, 0) << minus_camera.output;
  const std::set<std::string> all_ids = ids(all.output);
  std::set<std::string> expected;
  for (const std::string& id : all_ids)
    if (id.rfind("camera.", 0) != 0) expected.insert(id);
  ASSERT_LT(expected.size(), all_ids.size());
  EXPECT_EQ(ids(no_camera.output), expected);
  EXPECT_EQ(ids(minus_camera.output), expected);
  // One check excluded from a group.
  const CommandResult one = run("layer,-layer.depth-finite");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  std::set<std::string> layer_ids;
  for (const std::string& id : all_ids)
    if (id.rfind("layer.", 0) == 0 && id != "layer.depth-finite") layer_ids.insert(id);
  EXPECT_GT(layer_ids.size(), 1u);
  EXPECT_EQ(ids(one.output), layer_ids);
  const CommandResult unknown = run("all,camrea");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.output.find("unknown check 'camrea' (did you mean 'camera'?)"),
            std::string::npos)
      << unknown.output;
  // The deprecated --jobs still works, with a warning; --threads is the flag.
  const CommandResult jobs =
      RunCommandLine(Lsds() + " validate " + C() + " --checks schema --jobs 1");
  EXPECT_EQ(jobs.exit_code, 0) << jobs.output;
  EXPECT_NE(jobs.output.find("--jobs is deprecated; use --threads"), std::string::npos);
  EXPECT_EQ(RunCommandLine(Lsds() + " validate " + C() + " --checks schema --threads 1").exit_code,
            0);
}

TEST_F(CliGrammar, BackprojectOneFrameToANamedFile) {
  testing::TempDir out;
  const CommandResult one = RunCommandLine(Lsds() + " backproject " + C() + " --frames 0:1 -o " +
                                           (out / "f0.pcd").string());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_TRUE(fs::is_regular_file(out / "f0.pcd"));
  // Its points are those of frame 0 written per frame.
  ASSERT_EQ(
      RunCommandLine(Lsds() + " backproject " + C() + " --frames 0 -o " + (out / "per").string())
          .exit_code,
      0);
  EXPECT_EQ(fs::file_size(out / "f0.pcd"), fs::file_size(out / "per" / "000000.pcd"));
  // Several frames into one file still need --fuse, and say so.
  const CommandResult two = RunCommandLine(Lsds() + " backproject " + C() + " --frames 0:2 -o " +
                                           (out / "f01.pcd").string());
  EXPECT_EQ(two.exit_code, 2);
  EXPECT_NE(two.output.find("--frames N"), std::string::npos) << two.output;
}

}  // namespace
}  // namespace lsds

namespace lsds {
namespace {

// After an interrupt the output holds generate's work folder; a rerun without
// --resume points to --resume (not --force, which deletes the frames), and
// --resume finishes the collection.
TEST(CliResumeHint, ARerunAfterAnInterruptPointsToResume) {
  testing::TempDir out;
  const std::string base = testing::LsdsBinary() +
                           " generate --demo --demo-frames 2 --demo-size 16x16 "
                           "--spp 1 -q -o " +
                           (out / "g").string();
  // What an interrupted run leaves is generate's work folder in the output:
  // a finished collection with that folder recreated stands for it.
  ASSERT_EQ(testing::RunCommandLine(base).exit_code, 0);
  std::filesystem::create_directories(out / "g" / ".lsds-generate");
  const testing::CommandResult rerun = testing::RunCommandLine(base);
  EXPECT_EQ(rerun.exit_code, 2);
  EXPECT_NE(rerun.output.find("pass --resume to finish it"), std::string::npos) << rerun.output;
  const testing::CommandResult resumed = testing::RunCommandLine(base + " --resume");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_TRUE(std::filesystem::exists(out / "g" / "collection.json"));
}

// The frames of the error findings of a `lsds validate --format json` report.
std::set<int64_t> FramesWithErrors(const nlohmann::json& report) {
  std::set<int64_t> frames;
  for (const auto& check : report["checks"])
    for (const auto& finding : check["findings"])
      if (finding["severity"] == "error" && finding["location"].contains("frame"))
        frames.insert(finding["location"]["frame"].get<int64_t>());
  return frames;
}

// validate --frames checks the selected frames only: a defect planted in frame
// 2 (a layer file removed) is found exactly when frame 2 is selected, and the
// report counts the selected frames.
TEST_F(CliGrammar, ValidateChecksTheSelectedFrames) {
  testing::TempDir out;
  synth::Spec spec = synth::DefaultSpec();  // frames 0..3
  spec.width = 32, spec.height = 24;
  synth::WriteCollection(out / "c", spec);
  const nlohmann::json header = ReadJson(out / "c" / "collection.json");
  const nlohmann::json& files = header["frames"][2]["files"];
  ASSERT_FALSE(files.empty());
  fs::remove(out / "c" / files.begin()->get<std::string>());
  const std::string base = Lsds() + " validate " + (out / "c").string() + " --format json -o ";
  struct Case {
    std::string frames;
    int64_t count;
    bool finds_frame_2;
  };
  for (const Case& c : {Case{"0:2", 2, false}, Case{"2", 1, true}, Case{"1:", 3, true}}) {
    const fs::path report = out / ("r" + c.frames.substr(0, 1) + ".json");
    const CommandResult result =
        RunCommandLine(base + report.string() + " --frames " + c.frames + " --force");
    const nlohmann::json json = ReadJson(report);
    EXPECT_EQ(json["frames"].get<int64_t>(), c.count) << c.frames << "\n" << result.output;
    EXPECT_EQ(FramesWithErrors(json).count(2) > 0, c.finds_frame_2) << c.frames;
    EXPECT_EQ(result.exit_code, c.finds_frame_2 ? 1 : 0) << c.frames << "\n" << result.output;
  }
}

// The common flags of docs/cli.md ("Flags shared by every command"), as the
// help of every command must list them.
const char* const kCommonFlags[] = {
    "--frames", "--threads", "-q,--quiet", "--force", "--memory-budget"};

// The commands `lsds help` lists (two spaces, then the name).
std::vector<std::string> ListedCommands() {
  const testing::CommandResult help = testing::RunLsds("help");
  std::vector<std::string> names;
  std::istringstream lines(help.output);
  bool in_list = false;
  for (std::string line; std::getline(lines, line);) {
    if (line == "commands:")
      in_list = true;
    else if (in_list && line.rfind("  ", 0) == 0)
      names.push_back(line.substr(2, line.find(' ', 2) - 2));
    else if (in_list && !names.empty())
      break;
  }
  return names;
}

TEST(CliHelp, EveryCommandListsTheCommonFlags) {
  const std::vector<std::string> commands = ListedCommands();
  ASSERT_GE(commands.size(), 16u);
  for (const std::string& command : commands) {
    const testing::CommandResult help = testing::RunLsds(command + " --help");
    ASSERT_EQ(help.exit_code, 0) << command << "\n" << help.output;
    for (const char* flag : kCommonFlags) {
      // An option line of CLI11's help: the flag, then its value or help text.
      const bool listed = help.output.find("  " + std::string(flag) + " ") != std::string::npos;
      EXPECT_TRUE(listed) << "lsds " << command << " --help does not list " << flag << "\n"
                          << help.output;
    }
  }
}

// A common flag a command has no use for is refused, naming the flag and why,
// never silently ignored; the same flag works where it means something.
TEST_F(CliGrammar, AnUnusedCommonFlagIsExit2NamingIt) {
  struct Case {
    std::string args;
    std::string prefix;
  };
  testing::TempDir out;
  for (const Case& c : {Case{"info " + C() + " --frames 1", "lsds info: error: --frames 1: "},
                        Case{"info " + C() + " --force", "lsds info: error: --force: "},
                        Case{"merge " + C() + " -o " + (out / "m").string() + " --frames 0:2",
                             "lsds merge: error: --frames 0:2: "},
                        Case{"import kubric " + C() + " -o " + (out / "i").string() + " --frames 0",
                             "lsds import: error: --frames 0: "}}) {
    const testing::CommandResult result = testing::RunLsds(c.args);
    EXPECT_EQ(result.exit_code, 2) << c.args << "\n" << result.output;
    EXPECT_EQ(result.output.rfind(c.prefix, 0), 0u) << c.args << "\n" << result.output;
  }
  EXPECT_FALSE(fs::exists(out / "m"));
  EXPECT_FALSE(fs::exists(out / "i"));
  // -q and --threads are taken by every command, also by those that run on one thread.
  const testing::CommandResult info = testing::RunLsds("info " + C() + " -q --threads 1");
  EXPECT_EQ(info.exit_code, 0) << info.output;
}

// `lsds help` takes the formats from the registries: every one is listed, as a whole word.
TEST(CliHelp, ListsEveryConverterAndImporter) {
  const testing::CommandResult help = testing::RunLsds("help");
  ASSERT_EQ(help.exit_code, 0) << help.output;
  const auto listed = [&](const std::string& name) {
    for (const char* after : {",", ")", " "})
      if (help.output.find(name + after) != std::string::npos) return true;
    return false;
  };
  for (const std::string& name : convert::ConverterNames()) EXPECT_TRUE(listed(name)) << name;
  for (const std::string& name : import::ImporterNames()) EXPECT_TRUE(listed(name)) << name;
}

}  // namespace
}  // namespace lsds
