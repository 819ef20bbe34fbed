// The reliability pieces of libs/util on inputs whose answer is known: the
// output guard (is / contains / lies inside, symlinks, containers), the folder
// lock between two writers, the nesting pre-scan, the memory budget and the
// regular-file rule.
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "libs/util/check.h"
#include "libs/util/error.h"
#include "libs/util/folder_lock.h"
#include "libs/util/input_file.h"
#include "libs/util/limits.h"
#include "libs/util/output_guard.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;

std::string Refusal(const OutputGuard& guard, const fs::path& output) {
  try {
    guard.CheckOutput(output, "-o");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(OutputGuard, RefusesIsContainsAndInside) {
  testing::TempDir dir;
  fs::create_directories(dir / "C" / "rgb");
  std::ofstream(dir / "C" / "collection.json") << "{}";
  OutputGuard guard("lsds test");
  guard.AddInput(dir / "C", "collection folder");
  EXPECT_NE(Refusal(guard, dir / "C").find(" is the collection folder"), std::string::npos);
  EXPECT_NE(Refusal(guard, dir / "C" / "x" / ".." / "rgb" / "a.exr").find("lies inside"),
            std::string::npos);
  EXPECT_NE(Refusal(guard, dir.path()).find("contains"), std::string::npos);
  EXPECT_EQ(Refusal(guard, dir / "out"), "");
  EXPECT_EQ(Refusal(guard, dir / "C2"), "");  // a prefix of a name is not inside
  // The message names both paths.
  const std::string message = Refusal(guard, dir / "C" / "collection.json");
  EXPECT_NE(message.find((dir / "C" / "collection.json").string()), std::string::npos);
  EXPECT_NE(message.find("even with --force"), std::string::npos);
}

TEST(OutputGuard, SeesThroughSymlinks) {
  testing::TempDir dir;
  fs::create_directories(dir / "data" / "rgb");
  fs::create_directories(dir / "C");
  fs::create_directory_symlink(dir / "data" / "rgb", dir / "C" / "rgb");
  fs::create_directory_symlink(dir / "C", dir / "L");
  OutputGuard guard("lsds test");
  guard.AddInput(dir / "C", "collection folder");
  guard.AddSymlinkTargetsIn(dir / "C");
  EXPECT_NE(Refusal(guard, dir / "L" / "out").find("lies inside"), std::string::npos);
  EXPECT_NE(Refusal(guard, dir / "data" / "rgb" / "x.exr").find("target of the symlink"),
            std::string::npos);
  EXPECT_EQ(Refusal(guard, dir / "data" / "other"), "");
}

TEST(OutputGuard, ContainerAllowsOutputsInsideOnly) {
  testing::TempDir dir;
  fs::create_directories(dir / "C" / "depth");
  OutputGuard guard("lsds test");
  guard.AddInput(dir / "C" / "depth", "layer folder");
  guard.AddContainer(dir / "C", "collection folder");
  EXPECT_EQ(Refusal(guard, dir / "C" / "metadata.x.json"), "");
  EXPECT_NE(Refusal(guard, dir / "C" / "depth" / "m.json"), "");
  EXPECT_NE(Refusal(guard, dir / "C"), "");
  EXPECT_NE(Refusal(guard, dir.path()), "");
}

TEST(FolderLock, SecondWriterWaitsThenFailsNamingTheFolder) {
  testing::TempDir dir;
  setenv("LSDS_LOCK_TIMEOUT", "0.3", 1);
  {
    const FolderLock first(dir.path(), "test");
    try {
      const FolderLock second(dir.path(), "test");
      ADD_FAILURE() << "the second lock was granted while the first is held";
    } catch (const Error& e) {
      EXPECT_EQ(e.location().file, dir.path().string());
      EXPECT_NE(e.message().find("LSDS_LOCK_TIMEOUT"), std::string::npos);
    }
  }
  // Released: the next writer gets it at once.
  const FolderLock third(dir.path(), "test");
  unsetenv("LSDS_LOCK_TIMEOUT");
}

TEST(FolderLock, SerializesWriters) {
  testing::TempDir dir;
  auto first = std::make_unique<FolderLock>(dir.path(), "test");
  std::atomic<bool> released{false};
  auto second = std::async(std::launch::async, [&] {
    const FolderLock lock(dir.path(), "test");
    return released.load();
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  released = true;
  first.reset();
  EXPECT_TRUE(second.get());  // granted only after the first let go
}

TEST(Limits, NestingPrescanNamesLineAndColumn) {
  std::string deep = "{\n  \"a\": ";
  for (int i = 0; i < 1000; ++i) deep += "[";
  try {
    CheckJsonNesting(deep, "x.json");
    FAIL() << "1000 levels accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.location().file, "x.json");
    EXPECT_EQ(e.location().line, 2);
    EXPECT_EQ(e.location().column, 7 + kMaxNestingDepth);
  }
  // Brackets inside strings do not count; the limit itself is accepted.
  std::string fine = "{\"s\": \"" + std::string(5000, '[') + "\", \"a\": ";
  for (int i = 1; i < kMaxNestingDepth; ++i) fine += "[";
  EXPECT_NO_THROW(CheckJsonNesting(fine, "y.json"));
}

TEST(Limits, ImageBudgetBeforeAllocation) {
  SetMemoryBudget("1M");
  EXPECT_NO_THROW(CheckImageBudget(256, 256, 4, 4, "image", "--size"));
  try {
    CheckImageBudget(1024, 1024, 4, 4, "image", "--size");
    FAIL() << "16 MiB accepted under a 1 MiB budget";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("16.0 MiB"), std::string::npos);  // the need
    EXPECT_NE(e.message().find("budget of 1.0 MiB"), std::string::npos);
    EXPECT_NE(e.message().find("--memory-budget"), std::string::npos);
  }
  // Hostile factors do not wrap around.
  EXPECT_THROW(CheckImageBudget(int64_t{1} << 40, int64_t{1} << 40, 1 << 20, 8, "image", "--size"),
               Error);
  EXPECT_THROW(SetMemoryBudget("lots"), Error);
  EXPECT_EQ(ParseByteSize("2G", "x"), uint64_t{2} << 30);
  SetMemoryBudget("8G");
}

TEST(InputFile, OnlyRegularFiles) {
  testing::TempDir dir;
  const fs::path fifo = dir / "f";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THROW(RequireRegularFile(fifo, "scene file"), Error);
  EXPECT_THROW(RequireRegularFile(dir.path(), "scene file"), Error);
  EXPECT_THROW(RequireRegularFile(dir / "missing"), Error);
  std::ofstream(dir / "ok") << "x";
  EXPECT_NO_THROW(RequireRegularFile(dir / "ok"));
}

TEST(Check, FailedCheckIsAnInternalError) {
  EXPECT_THROW(LSDS_CHECK(1 + 1 == 3), InternalError);
  EXPECT_NO_THROW(LSDS_CHECK(1 + 1 == 2));
  try {
    LSDS_CHECK_MSG(false, "detail");
  } catch (const InternalError& e) {
    EXPECT_NE(std::string(e.what()).find("reliability_test.cc"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("detail"), std::string::npos);
  }
}

}  // namespace
}  // namespace lsds
