// The dual layer end to end (issue 6): haptex launch runs the pinch_stretch scene with real
// processes over loopback UDP: the mock GRAB controller (an artificial user pinching and
// stretching denim), the device bridge (5 kHz), local_contact (1 kHz) and global_sim (100 Hz).
// The user's fingers must feel the pinch (state VIII, force through the bridge to the mock), the
// patches must flow both ways, and stopping ends with zero force.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <string>

#include "tests/support/fresh_dir.h"
#include "tests/support/mock_force_log.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex::local_contact {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The number after "key": in the part of `json` that follows `after`.
double NumberAfter(const std::string& json, const std::string& after, const std::string& key) {
  const auto at = json.find(after);
  if (at == std::string::npos) return -1.0;
  std::smatch m;
  const std::string tail = json.substr(at);
  if (!std::regex_search(tail, m, std::regex("\"" + key + "\":(-?[0-9.eE+-]+)"))) return -1.0;
  return std::stod(m[1].str());
}

TEST(DualLayerProcessTest, PinchAndStretchIsFeltAndEndsAtZeroForce) {
  const std::string run = haptex::testing::FreshDir("dual_layer_process") + "/run";
  haptex::testing::Subprocess launcher({haptex::testing::BuildDir() + "/cli/haptex", "launch",
                                        haptex::testing::SourceDir() + "/launch/scenes/pinch_stretch.textproto",
                                        "--duration", "6", "--out", run});
  const std::optional<int> code = launcher.WaitFor(std::chrono::seconds(120));
  ASSERT_TRUE(code.has_value()) << "launcher still running\n" << launcher.Stdout();
  ASSERT_EQ(*code, 0) << launcher.Stdout() << launcher.Stderr();
  const std::string summary = ReadText(run + "/summary.json");

  // local_contact classified a pinch and sent force models; global_sim cut patches and merged
  // local_contact's results.
  EXPECT_GT(NumberAfter(summary, "\"name\":\"local_contact\"", "state_VIII_ticks"), 100) << summary;
  EXPECT_GT(NumberAfter(summary, "\"name\":\"local_contact\"", "patch_handoffs"), 50);
  EXPECT_GT(NumberAfter(summary, "\"name\":\"local_contact\"", "patch_results_sent"), 50);
  EXPECT_GT(NumberAfter(summary, "\"name\":\"global_sim\"", "patches_sent"), 50);
  EXPECT_GT(NumberAfter(summary, "\"name\":\"global_sim\"", "patch_results_merged"), 50);
  EXPECT_EQ(NumberAfter(summary, "\"name\":\"global_sim\"", "fabric_nan_events"), 0);

  // The force reached the mock's fingers (through the bridge's safety stage) and ended at zero.
  double peak_thumb = 0.0, peak_index = 0.0, last_thumb = -1.0, last_index = -1.0;
  int rows = 0;
  for (const haptex::testing::ForceRow& r : haptex::testing::MockForceRows(run + "/mock_grab_forces.csv")) {
    last_thumb = r.thumb_N;
    last_index = r.index_N;
    peak_thumb = std::max(peak_thumb, last_thumb);
    peak_index = std::max(peak_index, last_index);
    ++rows;
  }
  ASSERT_GT(rows, 1000);
  EXPECT_GT(peak_thumb, 0.5);
  EXPECT_GT(peak_index, 0.5);
  EXPECT_EQ(last_thumb, 0.0);
  EXPECT_EQ(last_index, 0.0);
  std::printf("[dual-process] peak commanded force thumb %.2f N index %.2f N over %d controller ticks\n", peak_thumb,
              peak_index, rows);
}

}  // namespace
}  // namespace haptex::local_contact
