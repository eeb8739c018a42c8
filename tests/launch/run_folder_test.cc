// Run folders from hostile scene names: always a new folder directly inside its parent, whose name
// holds only safe bytes; two launches in the same second get two folders.
#include "launch/run_folder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <set>

#include "tests/launch/hostile_names.h"
#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

namespace fs = std::filesystem;

TEST(LaunchRunFolderTest, SlugsAreOneSafePathComponent) {
  const std::regex safe("[A-Za-z0-9_-][A-Za-z0-9._-]*");
  for (const std::string& name : testing::HostileNames("/tmp/never")) {
    const std::string slug = RunFolderSlug(name);
    EXPECT_TRUE(std::regex_match(slug, safe)) << slug;
    EXPECT_LE(slug.size(), kMaxRunSlugBytes);
  }
  EXPECT_EQ(RunFolderSlug("demo"), "demo");
  EXPECT_EQ(RunFolderSlug("pinch_stretch-2.v1"), "pinch_stretch-2.v1");
  EXPECT_EQ(RunFolderSlug("../../x"), "_._.._x");
  EXPECT_EQ(RunFolderSlug(""), "scene");
  EXPECT_EQ(RunFolderStem("a b", "20260101-120000", "lab/1"), "a_b-20260101-120000-lab_1");
}

TEST(LaunchRunFolderTest, HostileNamesStayInsideTheParent) {
  const std::string runs = testing::FreshDir("run_folder_hostile") + "/runs";
  std::set<std::string> made;
  for (const std::string& name : testing::HostileNames("/tmp/never")) {
    const std::string dir = CreateUniqueRunFolder(runs, RunFolderStem(name, "20260101-120000", ""));
    EXPECT_TRUE(fs::is_directory(dir)) << dir;
    EXPECT_EQ(fs::path(dir).parent_path(), fs::path(runs)) << dir;
    EXPECT_EQ(fs::canonical(dir).parent_path(), fs::canonical(runs)) << dir;
    EXPECT_TRUE(made.insert(dir).second) << "shared: " << dir;
  }
  // nothing was made beside runs/
  std::size_t beside = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(runs).parent_path())) beside += entry.path() != runs;
  EXPECT_EQ(beside, 0u);
}

TEST(LaunchRunFolderTest, LaunchesInTheSameSecondGetTheirOwnFolder) {
  const std::string runs = testing::FreshDir("run_folder_same_second");
  const std::string stem = RunFolderStem("demo", "20260101-120000", "");
  const std::string first = CreateUniqueRunFolder(runs, stem);
  const std::string second = CreateUniqueRunFolder(runs, stem);
  const std::string third = CreateUniqueRunFolder(runs, stem);
  EXPECT_EQ(first, runs + "/demo-20260101-120000");
  EXPECT_EQ(second, runs + "/demo-20260101-120000-2");
  EXPECT_EQ(third, runs + "/demo-20260101-120000-3");
}

TEST(LaunchRunFolderTest, AnUncreatableParentIsAClearError) {
  const std::string file = testing::FreshDir("run_folder_file") + "/not_a_folder";
  testing::WriteText(file, "x");
  EXPECT_ANY_THROW(CreateUniqueRunFolder(file + "/runs", "demo"));
}

// What a full disk or a folder in the way does to a run's record: an error with the reason.
TEST(LaunchRunFolderTest, AFileThatCannotBeWrittenIsAnErrorWithTheReason) {
  const std::string dir = testing::FreshDir("run_folder_write");
  WriteRunFile(dir + "/summary.json", "{\"a\":1}");
  EXPECT_EQ(testing::ReadText(dir + "/summary.json"), "{\"a\":1}");

  auto message = [](const std::string& path, std::string_view text) {
    try {
      WriteRunFile(path, text);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // /dev/full fails every write with ENOSPC, as a full disk does
  EXPECT_EQ(message("/dev/full", std::string(100000, 'x')), "cannot write /dev/full: No space left on device");
  EXPECT_EQ(message("/dev/full", "{}"), "cannot write /dev/full: No space left on device");
  fs::create_directories(dir + "/in_the_way.json");
  EXPECT_EQ(message(dir + "/in_the_way.json", "{}"), "cannot write " + dir + "/in_the_way.json: Is a directory");
  EXPECT_EQ(message(dir + "/no/such/folder.json", "{}"),
            "cannot write " + dir + "/no/such/folder.json: No such file or directory");
}

}  // namespace
}  // namespace haptex::launch
