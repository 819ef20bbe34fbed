// The --frames grammar (libs/util/frame_selection.h) on known answers.
#include "libs/util/frame_selection.h"

#include <gtest/gtest.h>

#include "libs/util/error.h"

namespace lsds {
namespace {

TEST(FrameSelection, TheFourFormsAreAPythonSlice) {
  struct Case {
    const char* text;
    int64_t begin, end;
  };
  const int64_t kEnd = FrameSelection::kToTheEnd;
  for (const Case& c : {Case{"1:3", 1, 3},
                        Case{"2:", 2, kEnd},
                        Case{":2", 0, 2},
                        Case{"2", 2, 3},  // N is frame N alone, as x[N]
                        Case{"0", 0, 1},
                        Case{":", 0, kEnd}}) {
    const FrameSelection s = ParseFrameSelection(c.text);
    EXPECT_EQ(s.begin, c.begin) << c.text;
    EXPECT_EQ(s.end, c.end) << c.text;
  }
}

TEST(FrameSelection, BadTextIsALocatedError) {
  for (const char* text : {"a:b", "3:1", "2:2", "-1", "1:2:3", "", "1.5", "+2"}) {
    try {
      ParseFrameSelection(text);
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--frames " + std::string(text), 0), 0u) << e.what();
    }
  }
}

TEST(FrameSelection, OutOfRangeNamesTheValidRange) {
  const std::vector<int64_t> frames = {0, 1, 2, 3};
  for (const char* ok : {"0:4", "3", ":", "1:", ":4"})
    EXPECT_NO_THROW(CheckFrameSelection(ParseFrameSelection(ok), frames, "the collection")) << ok;
  for (const char* bad : {"4", "4:6", "2:5", "100:"}) {
    try {
      CheckFrameSelection(ParseFrameSelection(bad), frames, "the collection");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("indices 0 to 3"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--frames 0:4"), std::string::npos) << e.what();
    }
  }
  // A sharded collection with a gap: a selection inside the gap selects none.
  EXPECT_THROW(CheckFrameSelection(ParseFrameSelection("2:4"), {0, 1, 4, 5}, "the collection"),
               Error);
  EXPECT_NO_THROW(CheckFrameSelection(ParseFrameSelection("1:5"), {0, 1, 4, 5}, "the collection"));
}

}  // namespace
}  // namespace lsds
