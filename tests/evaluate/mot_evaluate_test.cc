// lsds evaluate --format mot: TrackEval tracker files read as the collection's
// frames; the truth converted by lsds convert --to mot (visible boxes) scores
// AP 1; bad files are named at their line (exit 2, nothing written).
#include <string>

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
  // Two categories: tracker rows say no class, so the truth must have one.
  const testing::CommandResult two = testing::RunLsds(base);
  EXPECT_EQ(two.exit_code, 2) << two.output;
  EXPECT_NE(two.output.find("carry no class"), std::string::npos) << two.output;
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
