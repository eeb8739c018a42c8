#pragma once
// A test's own temp folder, removed when the test passes and kept for reading when it fails.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace haptex::testing {

/// Removes the folders of a test that passed when it ends; a failed test keeps its run folders to be
/// read. A whole suite's runs would otherwise leave about 1.5 GB behind (recordings, run.mcap, the
/// force logs), enough to fill a small disk within a few runs.
class FreshDirRemover : public ::testing::EmptyTestEventListener {
 public:
  void Add(const std::string& dir) { dirs_.push_back(dir); }
  void OnTestEnd(const ::testing::TestInfo& test) override {
    if (test.result()->Passed()) {
      for (const std::string& dir : dirs_) {
        std::error_code ignored;
        std::filesystem::remove_all(dir, ignored);
      }
    }
    dirs_.clear();
  }

 private:
  std::vector<std::string> dirs_;
};

/// A fresh folder under the test temp dir, for the current test only (removed when it passes).
inline std::string FreshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/" + name + "_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  // gtest owns the listener once appended
  static FreshDirRemover* const remover = [] {
    auto* listener = new FreshDirRemover;
    ::testing::UnitTest::GetInstance()->listeners().Append(listener);
    return listener;
  }();
  remover->Add(dir);
  return dir;
}

}  // namespace haptex::testing
