// lsds evaluate --format mot: TrackEval tracker files read as the collection's
// frames; the truth converted by lsds convert --to mot (visible boxes) scores
// AP 1; bad files are named at their line (exit 2, nothing written).
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "libs/util/atomic_file.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "tests/evaluate/golden_fixture.h"

namespace lsds::evaluate {
namespace {

namespace fs = std::filesystem;

using MotEvaluate = GoldenCollection;

TEST_F(MotEvaluate, TheTruthConvertedToMotScoresOne) {
  testing::TempDir out;
  // One class (tracker files carry none), the tight visible boxes the COCO truth has.
  const testing::CommandResult convert =
      testing::RunLsds("convert " + C() +
                       " --to mot --classes box --mot-box visible --images none "
                       "-q -o " +
                       (out / "mot").string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  fs::create_directories(out / "tracker");
  int sequences = 0;
  for (const auto& split : fs::directory_iterator(out / "mot" / "mot" / "LSDS-train")) {
    // gt.txt's rows are `frame,id,x,y,w,h,1,class,visibility`: a tracker row with conf 1.
    fs::copy_file(split.path() / "gt" / "gt.txt",
                  out / "tracker" / (split.path().filename().string() + ".txt"));
    ++sequences;
  }
  ASSERT_GE(sequences, 1);
  const std::string base =
      "evaluate " + C() + " --format mot -q --predictions " + (out / "tracker").string();
  const testing::CommandResult run =
      testing::RunLsds(base + " --classes box -o " + (out / "e.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json doc = ReadJsonFile(out / "e.json");
  EXPECT_EQ(doc["detections"], 40);  // the box objects of every frame, difficult ones too
  for (const char* metric : {"AP", "AP50", "AP75", "APs", "APm", "APl", "AR100"})
    EXPECT_EQ(doc["coco"][metric], 1.0) << metric;
  // Two categories: every row of these files is class 1 (box); the crates are missed.
  const testing::CommandResult two = testing::RunLsds(base + " -o " + (out / "two.json").string());
  ASSERT_EQ(two.exit_code, 0) << two.output;
  const nlohmann::json both = ReadJsonFile(out / "two.json");
  EXPECT_EQ(both["counts"]["matched_50"], 40);
  EXPECT_EQ(both["counts"]["objects"], 82);
}

// The sequences of `lsds convert --to mot` in `mot`, their gt.txt copied into
// `tracker` as tracker files (rows `frame,id,x,y,w,h,1,class,visibility`:
// conf 1, the class in the 8th field); `edit` may change each row.
int GtAsTrackerFiles(const fs::path& mot,
                     const fs::path& tracker,
                     const std::function<std::string(const std::string& sequence,
                                                     const std::string& row)>& edit = {}) {
  fs::create_directories(tracker);
  int sequences = 0;
  for (const auto& split : fs::directory_iterator(mot / "mot" / "LSDS-train")) {
    const std::string name = split.path().filename().string();
    std::istringstream rows(ReadTextFile(split.path() / "gt" / "gt.txt"));
    std::string text;
    for (std::string row; std::getline(rows, row);) text += edit ? edit(name, row) : row + "\n";
    WriteFileAtomic(tracker / (name + ".txt"), text);
    ++sequences;
  }
  return sequences;
}

// Row `frame,id,x,y,w,h,conf,class,...` with its class replaced.
std::string WithClass(const std::string& row, const std::string& mot_class) {
  std::vector<std::string> fields;
  std::istringstream in(row);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  fields[7] = mot_class;
  std::string out;
  for (const std::string& f : fields) out += (out.empty() ? "" : ",") + f;
  return out + "\n";
}

std::string ClassOf(const std::string& row) {
  std::vector<std::string> fields;
  std::istringstream in(row);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  return fields.size() > 7 ? fields[7] : "";
}

// A cube and a crate seen by a stereo pair flying 2 m at 5 m/s, 10 fps: 5
// steps, 10 frames, one MOT sequence per camera.
const char* const kRigScene =
    "LSCENE = ONE(W) ONE(CUBE) ONE(CRATE)\n"
    "W = terrain{size:[60,60]}\n"
    "CUBE = object{class:cube,extent:[2,2,2],position:{ON:W,within:[[-2.5,-0.5,-10],[-1.5,0.5,"
    "10]]}}\n"
    "CRATE = object{class:crate,extent:[2,2,1],position:{ON:W,within:[[1.5,-0.5,-10],[2.5,0.5,"
    "10]]}}\n";
const char* const kRigCapture =
    "LCAP = ONE(CO) ONE(P) ONE(CL)\n"
    "CO = camera{csettings:{fov:60,res:[96,72],fps:10},targets:[CUBE,CRATE],\n"
    "  rig:{left:{position:[-0.25,0,0]},right:{position:[0.25,0,0]}}}\n"
    "P = path{waypoints:{points:[[-1,0,20],[1,0,20]],speed:5}}\n"
    "CL = collection{CO:{move:[P]}}\n";

TEST(MotEvaluateRig, SeveralClassesAndCamerasScoreByTheClassColumn) {
  testing::TempDir dir;
  const std::string c = (dir / "C").string();
  const testing::CommandResult generate = GenerateFromText(dir.path(), kRigScene, kRigCapture);
  ASSERT_EQ(generate.exit_code, 0) << generate.output;
  const testing::CommandResult convert = testing::RunLsds(
      "convert " + c + " --to mot --mot-box visible --images none -q -o " + (dir / "mot").string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;

  // gt.txt of both cameras' sequences as tracker files: every object found.
  std::set<std::string> cameras;
  int rows = 0;
  ASSERT_EQ(GtAsTrackerFiles(dir / "mot",
                             dir / "all",
                             [&](const std::string& sequence, const std::string& row) {
                               cameras.insert(sequence.substr(sequence.rfind('-') + 1));
                               ++rows;
                               return row + "\n";
                             }),
            2);
  EXPECT_EQ(cameras, (std::set<std::string>{"left", "right"}));
  const std::string base = "evaluate " + c + " --format mot -q --predictions ";
  const testing::CommandResult all =
      testing::RunLsds(base + (dir / "all").string() + " -o " + (dir / "all.json").string());
  ASSERT_EQ(all.exit_code, 0) << all.output;
  const nlohmann::json perfect = ReadJsonFile(dir / "all.json");
  ASSERT_EQ(perfect["ground_truth"]["categories"].size(), 2u);
  EXPECT_EQ(perfect["detections"], rows);
  EXPECT_EQ(perfect["counts"]["objects"], rows);
  for (const char* metric : {"AP", "AP50", "AP75", "AR100"})
    EXPECT_EQ(perfect["coco"][metric], 1.0) << metric;

  // The right camera's crates left out: exactly those objects are missed,
  // and the class stratum says which.
  int dropped = 0;
  GtAsTrackerFiles(dir / "mot",
                   dir / "no-right-crates",
                   [&](const std::string& sequence, const std::string& row) {
                     if (sequence.size() > 6 && sequence.substr(sequence.size() - 6) == "-right" &&
                         ClassOf(row) == "2") {
                       ++dropped;
                       return std::string();
                     }
                     return row + "\n";
                   });
  ASSERT_GT(dropped, 0);
  const testing::CommandResult some = testing::RunLsds(base + (dir / "no-right-crates").string() +
                                                       " -o " + (dir / "some.json").string());
  ASSERT_EQ(some.exit_code, 0) << some.output;
  const nlohmann::json partial = ReadJsonFile(dir / "some.json");
  EXPECT_EQ(partial["counts"]["matched_50"], rows - dropped);
  EXPECT_EQ(partial["counts"]["false_positives_50"], 0);
  for (const nlohmann::json& condition : partial["conditions"]) {
    if (condition["name"] != "class") continue;
    EXPECT_EQ(condition["strata"][0]["label"], "crate");
    EXPECT_EQ(condition["strata"][0]["objects"].get<int>() -
                  condition["strata"][0]["matched_50"].get<int>(),
              dropped);
  }

  // The crates given the cube's class: each is a false positive of the cube
  // and a miss of the crate.
  GtAsTrackerFiles(dir / "mot", dir / "swapped", [&](const std::string&, const std::string& row) {
    return ClassOf(row) == "2" ? WithClass(row, "1") : row + "\n";
  });
  const testing::CommandResult swapped = testing::RunLsds(base + (dir / "swapped").string() +
                                                          " -o " + (dir / "swapped.json").string());
  ASSERT_EQ(swapped.exit_code, 0) << swapped.output;
  const nlohmann::json wrong = ReadJsonFile(dir / "swapped.json");
  int crates = 0;
  GtAsTrackerFiles(dir / "mot", dir / "count", [&](const std::string&, const std::string& row) {
    crates += ClassOf(row) == "2";
    return row + "\n";
  });
  EXPECT_EQ(wrong["counts"]["matched_50"], rows - crates);
  EXPECT_EQ(wrong["counts"]["false_positives_50"], crates);

  // Rows of 7 fields have no class column: TrackEval reads them as class 1,
  // the cube, so the crates are again false positives and misses.
  GtAsTrackerFiles(dir / "mot", dir / "seven", [&](const std::string&, const std::string& row) {
    std::string fields = row;
    for (int comma = 0, i = 0; i < static_cast<int>(fields.size()); ++i)
      if (fields[i] == ',' && ++comma == 7) fields.resize(i);
    return fields + "\n";
  });
  const testing::CommandResult seven =
      testing::RunLsds(base + (dir / "seven").string() + " -o " + (dir / "seven.json").string());
  ASSERT_EQ(seven.exit_code, 0) << seven.output;
  const nlohmann::json classless = ReadJsonFile(dir / "seven.json");
  EXPECT_EQ(classless["counts"]["matched_50"], rows - crates);
  EXPECT_EQ(classless["counts"]["false_positives_50"], crates);
  // Class 0 is no class of two.
  fs::create_directories(dir / "zero");
  WriteFileAtomic(dir / "zero" / fs::directory_iterator(dir / "all")->path().filename(),
                  "1,1,10,10,5,5,0.9,0\n");
  const testing::CommandResult zero =
      testing::RunLsds(base + (dir / "zero").string() + " -o " + (dir / "zero.json").string());
  EXPECT_EQ(zero.exit_code, 2) << zero.output;
  EXPECT_NE(zero.output.find(".txt:1"), std::string::npos) << zero.output;
  EXPECT_NE(zero.output.find("class 0 (8th field) is not a class"), std::string::npos)
      << zero.output;
  EXPECT_FALSE(fs::exists(dir / "zero.json"));
}

TEST_F(MotEvaluate, RowsOnTrackEvalsDistractorClassesAreLeftOut) {
  // --mot-classes mot17 with the crates renamed static_person (MOT17 class 7,
  // a distractor): rows on them are left out whatever their class, and the
  // crates count nowhere; rows on the boxes (pedestrian, 1) score as ever.
  testing::TempDir out;
  const std::string classes = " --classes box=pedestrian,crate=static_person --mot-classes mot17";
  const testing::CommandResult convert =
      testing::RunLsds("convert " + C() + " --to mot --mot-box visible --images none -q" + classes +
                       " -o " + (out / "mot").string());
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  int distractor_rows = 0;
  GtAsTrackerFiles(out / "mot", out / "tracker", [&](const std::string&, const std::string& row) {
    // The static persons' rows given the pedestrian class.
    if (ClassOf(row) != "7") return row + "\n";
    ++distractor_rows;
    return WithClass(row, "1");
  });
  ASSERT_GT(distractor_rows, 0);
  const testing::CommandResult run =
      testing::RunLsds("evaluate " + C() + " --format mot -q" + classes + " --predictions " +
                       (out / "tracker").string() + " -o " + (out / "e.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json doc = ReadJsonFile(out / "e.json");
  EXPECT_EQ(doc["counts"]["objects"], 40);  // the pedestrians (boxes) only
  EXPECT_EQ(doc["counts"]["matched_50"], 40);
  EXPECT_EQ(doc["counts"]["false_positives_50"], 0);
  EXPECT_EQ(doc["coco"]["AP"], 1.0);
  // Without the rule (--mot-classes order: class ids in output order, no
  // distractors) the same rows are false positives of the pedestrians.
  const testing::CommandResult order =
      testing::RunLsds("evaluate " + C() +
                       " --format mot -q --classes box=pedestrian,crate=static_person "
                       "--predictions " +
                       (out / "tracker").string() + " -o " + (out / "o.json").string());
  ASSERT_EQ(order.exit_code, 0) << order.output;
  const nlohmann::json plain = ReadJsonFile(out / "o.json");
  EXPECT_EQ(plain["counts"]["false_positives_50"], distractor_rows);
}

TEST_F(MotEvaluate, BadTrackerFilesAreNamedAtTheirLine) {
  struct BadCase {
    std::string file, text;
    std::string where, what;
  };
  const BadCase cases[] = {
      {"MOT17-02.txt", "1,1,10,10,5,5,0.9\n", "MOT17-02.txt", "not a sequence"},
      {"S1-shot0.txt", "1,1,10,10,5,5\n", "S1-shot0.txt:1", "got 6 fields"},
      {"S1-shot0.txt", "1,1,10,10,5,5,0.9\n99,1,10,10,5,5,0.9\n", "S1-shot0.txt:2", "frame 99"},
      {"S1-shot0.txt", "1,1,10,10,-5,5,0.9\n", "S1-shot0.txt:1", "negative width"},
      {"S1-shot0.txt", "1,1,10,inf,5,5,0.9\n", "S1-shot0.txt:1", "not a finite number"},
  };
  for (const BadCase& c : cases) {
    testing::TempDir out;
    fs::create_directories(out / "tracker");
    WriteFileAtomic(out / "tracker" / c.file, c.text);
    const testing::CommandResult run =
        testing::RunLsds("evaluate " + C() + " --classes box --format mot -q --predictions " +
                         (out / "tracker").string() + " -o " + (out / "e.json").string());
    EXPECT_EQ(run.exit_code, 2) << c.text << run.output;
    EXPECT_NE(run.output.find(c.where), std::string::npos) << c.text << run.output;
    EXPECT_NE(run.output.find(c.what), std::string::npos) << c.text << run.output;
    EXPECT_FALSE(fs::exists(out / "e.json"));
  }
}

}  // namespace
}  // namespace lsds::evaluate
