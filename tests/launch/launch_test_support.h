#pragma once
// Scenes for the launcher's tests: the shipped ones, and scenes written from text.

#include <gtest/gtest.h>
#include <unistd.h>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "libs/base/clock.h"
#include "libs/scene/scene_loader.h"
#include "tests/support/fresh_dir.h"
#include "tests/support/mock_force_log.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex::launch::testing {

inline scene::FabricDatabase Fabrics() { return scene::FabricDatabase(haptex::testing::SourceDir() + "/data/fabrics"); }

inline std::string ShippedScenePath(const std::string& name) {
  return haptex::testing::SourceDir() + "/launch/scenes/" + name + ".textproto";
}

inline v1::Scene ShippedScene(const std::string& name) {
  return scene::LoadScene(ShippedScenePath(name), Fabrics()).scene;
}

/// Parses and validates scene text (throws scene::TextProtoError).
inline v1::Scene SceneFromText(const std::string& text) {
  return scene::ParseScene(text, "test.textproto", Fabrics()).scene;
}

inline std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline void WriteText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

using haptex::testing::FreshDir;

/// Waits for a line matching `pattern` in a process's output; returns its first group (or the
/// whole match). Fails the test on timeout, or at once when the process ended without it.
inline std::string WaitForOutput(haptex::testing::Subprocess& p, const std::string& pattern,
                                 std::chrono::seconds timeout = std::chrono::seconds(90)) {
  const std::regex re(pattern);
  std::smatch match;
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    const std::string out = p.Stdout();
    if (std::regex_search(out, match, re)) return match.size() > 1 ? match[1].str() : match[0].str();
    if (p.WaitFor(std::chrono::milliseconds(0)).has_value()) {
      const std::string last = p.Stdout();
      if (std::regex_search(last, match, re)) return match.size() > 1 ? match[1].str() : match[0].str();
      break;  // it ended without printing it: no use waiting
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ADD_FAILURE() << "no output matching " << pattern << "\nstdout:\n" << p.Stdout() << "\nstderr:\n" << p.Stderr();
  return "";
}

using haptex::testing::ForceRow;
using haptex::testing::MockForceRows;

/// `haptex launch` of the shipped demo until Ctrl-C, into `run_dir`; its tactile pair (tactile,
/// mock_pins) skipped unless asked for.
inline std::vector<std::string> DemoLaunchArgv(const std::string& run_dir, bool with_tactile) {
  std::vector<std::string> argv{haptex::testing::BuildDir() + "/cli/haptex",
                                "launch",
                                ShippedScenePath("demo"),
                                "--duration",
                                "0",
                                "--out",
                                run_dir};
  if (!with_tactile) argv.insert(argv.end(), {"--skip", "tactile", "--skip", "mock_pins"});
  return argv;
}

/// Waits until every service runs; returns `service`'s pid (0 when it never started).
inline int RunningServicePid(haptex::testing::Subprocess& launcher, const std::string& service) {
  WaitForOutput(launcher, "running \\(until Ctrl-C\\)");
  const std::string pid = WaitForOutput(launcher, service + ": started \\(pid ([0-9]+)");
  return pid.empty() ? 0 : std::stoi(pid);
}

/// Waits until the mock's force log shows both fingers pressed (over 0.5 N each), at most 60 s.
inline bool WaitUntilBothFingersPress(const std::string& force_log_path) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const auto rows = MockForceRows(force_log_path);
    if (!rows.empty() && rows.back().thumb_N > 0.5 && rows.back().index_N > 0.5) return true;
  }
  return false;
}

}  // namespace haptex::launch::testing
