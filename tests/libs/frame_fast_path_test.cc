// The fast path of CollectionReader (json_array_split.h, frame_text_reader.h)
// against the DOM path (StreamJsonArrayMember, the frame schema and
// FrameFromJson): the same frames on the example collections, the fallback
// taking what the fast path refuses, and the DOM path's errors on corrupted
// files.
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "libs/collection/collection_read_once.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/frame_text_reader.h"
#include "libs/collection/json_array_split.h"
#include "libs/collection/json_io.h"
#include "libs/collection/json_stream.h"
#include "libs/util/error.h"
#include "tests/build_paths.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Path = CollectionReader::FramePath;

const std::vector<std::string> kExampleCollections = {
    "fuzz/corpus/collection/demo-collection.json",   // lsds generate --demo: scene, changes
    "fuzz/corpus/collection/synth-collection.json",  // lsds synth
    "fuzz/seed_collection/collection.json"};

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::vector<std::string> FramesAsJson(const CollectionReader& reader, Path path) {
  std::vector<std::string> frames;
  reader.ForEachFrame([&](const Frame& frame) { frames.push_back(FrameToJson(frame).dump()); },
                      path);
  return frames;
}

// The text of each element of "frames", as the fast path sees it.
std::vector<std::string> FrameTexts(const fs::path& file) {
  std::vector<std::string> texts;
  size_t done = 0;
  EXPECT_TRUE(SplitJsonArrayMember(
      file,
      "frames",
      nullptr,
      [&](std::string_view text, size_t) {
        texts.emplace_back(text);
        return true;
      },
      &done));
  EXPECT_EQ(done, texts.size());
  return texts;
}

// Reads `text` with the fast path (from a copy with the padding it needs).
bool FastRead(FrameTextReader& reader, const std::string& text, Frame* frame) {
  std::string padded = text + std::string(kElementTextPadding, ' ');
  return reader.Read(std::string_view(padded.data(), text.size()), frame);
}

// The message of the lsds::Error `fn` throws ("" when it throws none).
template <typename Fn>
std::string ErrorOf(const Fn& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(FrameFastPath, ExampleCollectionsGiveTheDomPathsFrames) {
  for (const std::string& example : kExampleCollections) {
    SCOPED_TRACE(example);
    const fs::path file = fs::path(testing::SourceDir()) / example;
    // The fast path takes every frame of these, and reads what FrameFromJson reads.
    FrameTextReader fast;
    const std::vector<std::string> texts = FrameTexts(file);
    ASSERT_FALSE(texts.empty());
    for (size_t k = 0; k < texts.size(); ++k) {
      Frame frame;
      ASSERT_TRUE(FastRead(fast, texts[k], &frame)) << "frame " << k;
      const Frame expected = FrameFromJson(json::parse(texts[k]), example, "/frames/0");
      EXPECT_EQ(FrameToJson(frame).dump(), FrameToJson(expected).dump());
      EXPECT_EQ(FrameToJson(frame).dump(), json::parse(texts[k]).dump());
    }
    // And the reader gives the same frames either way.
    testing::TempDir dir;
    fs::copy_file(file, dir / "collection.json");
    const CollectionReader reader(dir.path());
    EXPECT_EQ(reader.frames_in_file(), texts.size());
    const std::vector<std::string> fast_frames = FramesAsJson(reader, Path::kFastWhereItFits);
    EXPECT_EQ(fast_frames.size(), texts.size());
    EXPECT_EQ(fast_frames, FramesAsJson(reader, Path::kDomOnly));
  }
}

// Frames that are valid but written in ways the fast path leaves to the DOM
// path (a repeated key, which nlohmann takes last-wins), and spellings it
// takes (an escaped key, numbers written differently) read as nlohmann reads
// them.
TEST(FrameFastPath, FramesTheFastPathRefusesAreReadTheDomWay) {
  const fs::path file = fs::path(testing::SourceDir()) / kExampleCollections[1];
  const std::string original = ReadText(file);
  const std::vector<std::string> texts = FrameTexts(file);
  ASSERT_GE(texts.size(), 2u);
  const std::string& frame = texts[1];
  const auto edited = [&](const std::string& from, const std::string& to) {
    std::string text = frame;
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    return text;
  };
  const std::vector<std::string> quirky = {
      edited("\"time\":", "\"time\": 7.25, \"time\":"),
      edited("\"index\":", "\"sequence\": \"twice\", \"index\":"),
      edited("\"width\":", "\"width\": 4, \"width\":"),
  };
  FrameTextReader fast;
  for (const std::string& text : quirky) {
    SCOPED_TRACE(text);
    Frame frame_read;
    EXPECT_FALSE(FastRead(fast, text, &frame_read));
    std::string collection = original;
    collection.replace(collection.find(frame), frame.size(), text);
    testing::TempDir dir;
    WriteText(dir / "collection.json", collection);
    const CollectionReader reader(dir.path());
    const std::vector<std::string> fast_frames = FramesAsJson(reader, Path::kFastWhereItFits);
    EXPECT_EQ(fast_frames.size(), texts.size());
    EXPECT_EQ(fast_frames, FramesAsJson(reader, Path::kDomOnly));
  }
  // Spellings the fast path takes and reads as nlohmann does: an escaped key,
  // an integer token for a number, "-0", an exponent.
  std::vector<std::string> taken = {edited("\"time\":", "\"t\\u0069me\":")};
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"cx", "-0"}, {"time", "1E0"}, {"fx", "3"}, {"cy", "-2.5e-1"}}) {
    std::string text = frame;
    const size_t at = text.find("\"" + key + "\":") + key.size() + 3;
    text.replace(at, text.find_first_of(",}", at) - at, value);
    taken.push_back(text);
  }
  for (const std::string& text : taken) {
    SCOPED_TRACE(text);
    Frame frame_read;
    ASSERT_TRUE(FastRead(fast, text, &frame_read));
    EXPECT_EQ(FrameToJson(frame_read).dump(),
              FrameToJson(FrameFromJson(json::parse(text), "c", "/frames/1")).dump());
  }
}

// Corrupted frames: the fast path refuses them and the reader reports what
// the DOM path reports, word for word (file, JSON pointer, line:column).
TEST(FrameFastPath, CorruptedFramesGiveTheDomPathsErrors) {
  const fs::path file = fs::path(testing::SourceDir()) / kExampleCollections[1];
  const std::string original = ReadText(file);
  const std::string frame = FrameTexts(file).at(1);
  struct Corruption {
    std::string from, to;
  };
  const std::vector<Corruption> in_frames = {
      {"\"time\":", "\"tyme\": 0, \"time\":"},  // a key the schema does not allow
      {"\"fx\":", "\"fx\": -1, \"fy_\":"},      // out of range, then unknown
      {"\"depth/", "\"../depth/"},              // a reference out of the collection
      {"\"instance_id\":", "\"instance_id\": 0, \"x\":"},
  };
  for (const Corruption& c : in_frames) {
    SCOPED_TRACE(c.to);
    std::string text = frame;
    ASSERT_NE(text.find(c.from), std::string::npos);
    text.replace(text.find(c.from), c.from.size(), c.to);
    std::string collection = original;
    collection.replace(collection.find(frame), frame.size(), text);
    testing::TempDir dir;
    WriteText(dir / "collection.json", collection);
    const CollectionReader reader(dir.path());
    const std::string dom_error = ErrorOf([&] { FramesAsJson(reader, Path::kDomOnly); });
    EXPECT_NE(dom_error, "");
    EXPECT_NE(dom_error.find("/frames/1"), std::string::npos) << dom_error;
    EXPECT_EQ(ErrorOf([&] { FramesAsJson(reader, Path::kFastWhereItFits); }), dom_error);
  }
  // Syntax: the reader's constructor reports what the DOM stream reports.
  const std::vector<Corruption> syntax = {
      {"\"time\":", "\"time\": 1.5.2, \"t\":"},
      {"\"time\":", "\"time\": 1e999, \"t\":"},
      {"\"time\":", "\"time\": tru, \"t\":"},
      {"\"sequence\": \"", "\"sequence\": \"\x01"},
      {"\"time\":", std::string("\"time\": 1\0, \"t\":", 16)},
      {"\"time\":", "\"time\": 01, \"t\":"},
      {"\"time\":", "\"time\" 1, \"t\":"},
      {"\"time\":", "\"time\": [1}, \"t\":"},
  };
  for (const Corruption& c : syntax) {
    SCOPED_TRACE(c.to);
    std::string collection = original;
    const size_t at = collection.find(frame) + frame.find(c.from);
    collection.replace(at, c.from.size(), c.to);
    testing::TempDir dir;
    WriteText(dir / "collection.json", collection);
    const std::string dom_error = ErrorOf(
        [&] { StreamJsonArrayMember(dir / "collection.json", "frames", nullptr, nullptr); });
    EXPECT_NE(dom_error, "");
    EXPECT_EQ(ErrorOf([&] { CollectionReader reader(dir.path()); }), dom_error);
  }
  // The end of the file cut off.
  testing::TempDir dir;
  WriteText(dir / "collection.json", original.substr(0, original.size() - 4));
  const std::string dom_error =
      ErrorOf([&] { StreamJsonArrayMember(dir / "collection.json", "frames", nullptr, nullptr); });
  EXPECT_NE(dom_error, "");
  EXPECT_EQ(ErrorOf([&] { CollectionReader reader(dir.path()); }), dom_error);
}

// The frames and header of ReadCollectionOnce, with how many times it ran
// `read`.
struct ReadOnceResult {
  std::string header;
  std::vector<std::string> frames;
  int runs = 0;
};
ReadOnceResult ReadOnce(const fs::path& root) {
  ReadOnceResult result;
  const CollectionHeader last = ReadCollectionOnce(
      root, [&](const CollectionHeader& header, const ForEachFrameFn& for_each_frame) {
        ++result.runs;
        result.header = HeaderToJson(header).dump();
        result.frames.clear();
        for_each_frame(
            [&](const Frame& frame) { result.frames.push_back(FrameToJson(frame).dump()); });
      });
  EXPECT_EQ(HeaderToJson(last).dump(), result.header);
  return result;
}

// collection.json read once gives CollectionReader's header and frames (in one
// run where the frames are the last member, in two where members follow them)
// and its errors.
TEST(FrameFastPath, ReadOnceGivesTheReadersHeaderFramesAndErrors) {
  for (const std::string& example : kExampleCollections) {
    SCOPED_TRACE(example);
    const fs::path file = fs::path(testing::SourceDir()) / example;
    testing::TempDir dir;
    fs::copy_file(file, dir / "collection.json");
    const CollectionReader reader(dir.path());
    const ReadOnceResult once = ReadOnce(dir.path());
    EXPECT_EQ(once.runs, 1);
    EXPECT_EQ(once.header, HeaderToJson(reader.header()).dump());
    EXPECT_EQ(once.frames, FramesAsJson(reader, Path::kFastWhereItFits));
    ASSERT_FALSE(once.frames.empty());

    // A member after the frames (and the same member before them, which it
    // overrides, as nlohmann takes the last): the header of the whole file.
    json moved = json::parse(ReadText(file));
    json frames = moved["frames"];
    moved.erase("frames");
    json classes = moved["classes"];
    moved["classes"] = json::array();
    std::string text = moved.dump();
    text.pop_back();
    text += ",\"frames\":" + frames.dump() + ",\"classes\":" + classes.dump() + "}";
    WriteText(dir / "collection.json", text);
    const ReadOnceResult after = ReadOnce(dir.path());
    EXPECT_EQ(after.runs, 2);
    EXPECT_EQ(after.header, once.header);
    EXPECT_EQ(after.frames, once.frames);
  }
  const fs::path file = fs::path(testing::SourceDir()) / kExampleCollections[1];
  const std::string original = ReadText(file);
  const std::string frame = FrameTexts(file).at(1);
  // Syntax errors, a frame the schema refuses, a header the schema refuses
  // after the frames, the end cut off: CollectionReader's message.
  const std::vector<std::pair<std::string, std::string>> corruptions = {
      {"\"time\":", "\"time\": 1.5.2, \"t\":"},
      {"\"time\":", "\"time\": tru, \"t\":"},
      {"\"time\":", "\"time\": [1}, \"t\":"},
      {"\"time\":", "\"tyme\": 0, \"time\":"},
      {"\"fx\":", "\"fx\": -1, \"fy_\":"},
  };
  for (const auto& [from, to] : corruptions) {
    SCOPED_TRACE(to);
    std::string collection = original;
    const size_t at = collection.find(frame) + frame.find(from);
    collection.replace(at, from.size(), to);
    testing::TempDir dir;
    WriteText(dir / "collection.json", collection);
    const std::string error = ErrorOf([&] {
      const CollectionReader reader(dir.path());
      FramesAsJson(reader, Path::kFastWhereItFits);
    });
    EXPECT_NE(error, "");
    EXPECT_EQ(ErrorOf([&] { ReadOnce(dir.path()); }), error);
  }
  for (const std::string& tail : {std::string(",\"format_version\": 7}"), std::string("")}) {
    SCOPED_TRACE(tail);
    std::string collection = original.substr(0, original.rfind('}'));
    collection += tail;
    testing::TempDir dir;
    WriteText(dir / "collection.json", collection);
    const std::string error = ErrorOf([&] { CollectionReader reader(dir.path()); });
    EXPECT_NE(error, "");
    EXPECT_EQ(ErrorOf([&] { ReadOnce(dir.path()); }), error);
  }
}

// The syntax check never takes what nlohmann refuses.
TEST(FrameFastPath, WellFormedOnlyWhereNlohmannParses) {
  const std::vector<std::string> texts = {
      R"({"a": 1})",
      R"({"a": 1e999})",
      R"({"a": -})",
      R"({"a": 01})",
      R"({"a": 1.})",
      R"({"a": .5})",
      R"({"a": +1})",
      R"({"a": tru})",
      R"({"a": nul})",
      R"({"a": [1,]})",
      R"({"a": [1 2]})",
      R"({"a" 1})",
      R"({"a": 1,})",
      R"({"a": "\x"})",
      R"({"a": "\ud800"})",
      R"({"a": 1} x)",
      R"({"a": [}])",
      R"({"a": "é"})",
      R"({"a": -0})",
      R"({"a": 1E+2})",
      R"({"a": 18446744073709551616})",
      R"({"a": -9223372036854775809})",
      R"({"a": {"b": [true, false, null]}})",
      "{\"a\": \"\xff\"}",
      "{\"a\": \"\xc3\"}",
  };
  FrameTextReader reader;
  for (const std::string& text : texts) {
    SCOPED_TRACE(text);
    std::string padded = text + std::string(kElementTextPadding, ' ');
    const bool fast = reader.IsWellFormed(std::string_view(padded.data(), text.size()));
    bool parses = true;
    try {
      const json parsed = json::parse(text);
      EXPECT_TRUE(parsed.is_object());
    } catch (const json::exception&) {
      parses = false;
    }
    if (fast) {
      EXPECT_TRUE(parses);
    }
    if (text == R"({"a": 1})" || text == R"({"a": -0})") {
      EXPECT_TRUE(fast);
    }
  }
}

}  // namespace
}  // namespace lsds
