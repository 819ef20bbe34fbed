// The one atomic-output path and the shared text and number checks.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "libs/collection/json_stream.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"
#include "libs/util/text_check.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> Names(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// A temporary name as a process that no longer exists would have made it.
std::string DeadRunTempName(const std::string& target) {
  const std::string own = TempPathBeside(target).filename().string();
  // ".target.lsds-tmp-HOST-PID-N": swap PID for one that cannot be running.
  const size_t last = own.rfind('-');
  const size_t before = own.rfind('-', last - 1);
  return own.substr(0, before + 1) + "2147483646" + own.substr(last);
}

TEST(AtomicFile, TempNamesAreRecognizable) {
  const fs::path temp = TempPathBeside("/x/out.ply");
  EXPECT_EQ(temp.parent_path(), fs::path("/x"));
  const std::string name = temp.filename().string();
  EXPECT_EQ(name.rfind(".out.ply.lsds-tmp-", 0), 0u) << name;
  EXPECT_NE(name.find("-" + std::to_string(::getpid()) + "-"), std::string::npos);
  EXPECT_TRUE(IsTempName(name));
  EXPECT_FALSE(IsTempName("out.ply"));
  EXPECT_FALSE(IsTempName(".hidden"));
}

TEST(AtomicFile, CommitWritesAndAFailureLeavesNothing) {
  testing::TempDir dir;
  {
    AtomicFile file(dir / "a.txt");
    file.stream() << "hello";
    EXPECT_FALSE(fs::exists(dir / "a.txt"));
    file.Commit();
  }
  EXPECT_EQ(ReadFile(dir / "a.txt"), "hello");
  {
    AtomicFile file(dir / "b.txt");
    file.stream() << "never";
  }  // not committed: the temporary goes away
  EXPECT_EQ(Names(dir.path()), std::vector<std::string>{"a.txt"});
  // Seeking back (OpenEXR writes its offset table that way).
  {
    AtomicFile file(dir / "c.bin");
    file.stream() << "0123456789";
    file.stream().seekp(2);
    file.stream() << "ab";
    EXPECT_EQ(static_cast<int>(file.stream().tellp()), 4);
    file.Commit();
  }
  EXPECT_EQ(ReadFile(dir / "c.bin"), "01ab456789");
}

TEST(AtomicFile, LeftoversOfKilledRunsAreRemovedByTheNextWrite) {
  testing::TempDir dir;
  const std::string dead = DeadRunTempName("frame.exr");
  const std::string live = TempPathBeside(dir / "other.exr").filename().string();
  std::ofstream(dir / dead) << "partial";
  std::ofstream(dir / live) << "being written by this process";
  fs::create_directory(dir / "sub");
  std::ofstream(dir / "sub" / DeadRunTempName("x.json")) << "partial";
  EXPECT_EQ(RemoveStaleTemps(dir.path(), /*recursive=*/true), 2u);
  EXPECT_EQ(Names(dir.path()), (std::vector<std::string>{live, "sub"}));
  EXPECT_TRUE(fs::is_empty(dir / "sub"));
  // The first output into a folder sweeps it.
  fs::create_directory(dir / "out");
  std::ofstream(dir / "out" / dead) << "partial";
  WriteFileAtomic(dir / "out" / "result.json", "{}");
  EXPECT_EQ(Names(dir / "out"), std::vector<std::string>{"result.json"});
}

TEST(AtomicFile, JsonArrayWriterLeavesNoTemporaryWhenItsConstructorThrows) {
  testing::TempDir dir;
  // A header that cannot be written as JSON (not UTF-8): the constructor
  // throws after the temporary file exists.
  const nlohmann::json header = {{"name", std::string("caf\xE9")}};
  EXPECT_THROW(JsonArrayWriter(dir / "c.json", header, "frames"), nlohmann::json::exception);
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(AtomicFile, ReadingAFolderSaysSo) {
  testing::TempDir dir;
  try {
    ReadFile(dir.path());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos) << e.what();
  }
}

TEST(TextCheck, Utf8) {
  EXPECT_FALSE(FindInvalidUtf8("plain, caf\xC3\xA9, \xF0\x9F\x99\x82"));
  EXPECT_EQ(FindInvalidUtf8("caf\xE9"), 3u);            // Latin-1
  EXPECT_EQ(FindInvalidUtf8("ab\xC0\xAF"), 2u);         // overlong
  EXPECT_EQ(FindInvalidUtf8("\xED\xA0\x80"), 0u);       // surrogate
  EXPECT_EQ(FindInvalidUtf8("x\xF4\x90\x80\x80"), 1u);  // > U+10FFFF
  EXPECT_EQ(FindInvalidUtf8("ok\xE2\x82"), 2u);         // cut sequence
  try {
    CheckUtf8("a\nb # caf\xE9\n", "s.lscene");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.location().line, 2);
    EXPECT_EQ(e.location().column, 8);
    EXPECT_NE(e.message().find("0xE9"), std::string::npos) << e.what();
    EXPECT_NE(e.message().find("byte offset 9"), std::string::npos) << e.what();
  }
  EXPECT_EQ(Utf8Escaped("dir\xFFname"), "dir\\xFFname");
}

TEST(TextCheck, MessagesStayReadable) {
  const std::string huge(10 << 20, 'a');
  const Error error("unknown identifier '" + huge + "'", Location("s.lscene"));
  EXPECT_LT(std::string(error.what()).size(), 3000u);
  EXPECT_NE(std::string(error.what()).find("more bytes"), std::string::npos);
  EXPECT_EQ(Excerpt("a\x01"
                    "b"),
            "a\\x01b");
}

TEST(JsonErrors, OverflowAndSyntaxAreLocated) {
  const std::string text = "{\n  \"a\": 1,\n  \"b\": 1e999\n}";
  try {
    ParseJsonText(text, "f.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.location().line, 3);
    EXPECT_EQ(e.location().column, 8);
    EXPECT_NE(e.message().find("1e999"), std::string::npos) << e.what();
  }
  // A NUL byte inside the document is an error, not its end.
  const std::string with_nul = std::string("{\"a\": 1,\0 \"b\": 2}", 17);
  EXPECT_THROW(ParseJsonText(with_nul, "f.json"), Error);
  try {
    ParseJsonText("{\"a\": [1, 2,, 3]}", "f.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.location().line, 1);
    EXPECT_EQ(e.location().column, 13);
    EXPECT_NE(e.message().find("near '"), std::string::npos) << e.what();
  }
}

TEST(JsonErrors, IntegersAreRangeChecked) {
  const nlohmann::json j =
      nlohmann::json::parse(R"({"w": 4294967297, "n": -1, "f": 2.5, "ok": 32, "big": 4294967295})");
  EXPECT_THROW(GetInteger<int>(j, "w"), nlohmann::json::out_of_range);
  EXPECT_THROW(GetInteger<uint32_t>(j, "n"), nlohmann::json::out_of_range);
  EXPECT_THROW(GetInteger<int>(j, "f"), nlohmann::json::out_of_range);
  EXPECT_THROW(GetInteger<int>(j, "big"), nlohmann::json::out_of_range);
  EXPECT_EQ(GetInteger<uint32_t>(j, "big"), 4294967295u);
  EXPECT_EQ(GetInteger<int>(j, "ok"), 32);
  try {
    GetInteger<int>(j, "w");
  } catch (const nlohmann::json::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("w: 4294967297"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lsds
