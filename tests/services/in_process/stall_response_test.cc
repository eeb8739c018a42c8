// Pauses of the host against a held pinch, deterministically (services/in_process, the stall
// injector on the simulated clock): whatever pauses, for up to 30 ms, the force after the cut stays
// within the resume bound, the pinch holds again within 100 ms, and longer pauses end the contact
// at zero force, counted.
#include "services/in_process/stall_response.h"

#include <gtest/gtest.h>

#include <iostream>
#include <string>

#include "tests/support/test_paths.h"

namespace haptex::in_process {
namespace {

const scene::LoadedScene& PinchScene() {
  static const scene::LoadedScene scene =
      scene::LoadScene(haptex::testing::SourceDir() + "/launch/scenes/pinch_stretch.textproto",
                       scene::FabricDatabase(haptex::testing::SourceDir() + "/data/fabrics"));
  return scene;
}

// pinch_stretch holds its squeeze here (the stretch starts later)
constexpr double kStallAt_s = 4.5;

struct StallCase {
  const char* name;
  StallTarget target;
  double pause_ms;
};

class PinchStallTest : public ::testing::TestWithParam<StallCase> {};

TEST_P(PinchStallTest, ResumesWithinTheBoundAndHoldsAgain) {
  const StallCase c = GetParam();
  StallResponseOptions options;
  options.watch_after_s = 0.3;
  const StallResponse r = MeasureStall(PinchScene(), Stall{c.target, kStallAt_s, c.pause_ms / 1e3}, options);
  std::cout << "[measured] " << c.name << ": held " << r.fingers[0].held_N << " / " << r.fingers[1].held_N
            << " N, peak after " << r.fingers[0].peak_after_N << " / " << r.fingers[1].peak_after_N
            << " N, held again after " << r.held_again_after_s * 1e3 << " ms, largest reversal "
            << std::max(r.fingers[0].largest_reversal_N, r.fingers[1].largest_reversal_N) << " N\n";
  ASSERT_TRUE(r.pinched_before) << "not pinching when the stall began: the test would prove nothing";
  for (const FingerStallResponse& f : r.fingers) {
    ASSERT_GT(f.held_N, 3.0);
    EXPECT_LE(f.peak_after_N, ResumeBoundN(f.held_N) + 1e-9);
    EXPECT_LE(f.largest_step_N, 0.5 + 1e-9) << "faster than the slew limit";
    EXPECT_LT(f.largest_reversal_N, 1.0) << "a buzz";
  }
  EXPECT_LT(r.held_again_after_s, 0.100);
}

INSTANTIATE_TEST_SUITE_P(
    Pauses, PinchStallTest,
    ::testing::Values(StallCase{"device_bridge_5ms", StallTarget::kDeviceBridge, 5.0},
                      StallCase{"device_bridge_10ms", StallTarget::kDeviceBridge, 10.0},
                      StallCase{"device_bridge_30ms", StallTarget::kDeviceBridge, 30.0},
                      StallCase{"local_contact_10ms", StallTarget::kLocalContact, 10.0},
                      StallCase{"local_contact_30ms", StallTarget::kLocalContact, 30.0},
                      StallCase{"global_sim_30ms", StallTarget::kGlobalSim, 30.0},
                      StallCase{"mock_grab_30ms", StallTarget::kMockGrab, 30.0},
                      StallCase{"all_10ms", StallTarget::kAll, 10.0}, StallCase{"all_30ms", StallTarget::kAll, 30.0}),
    [](const ::testing::TestParamInfo<StallCase>& param) { return std::string(param.param.name); });

// A bridge paused 30 ms: the controller cut the force after 5 ms and the squeezing fingers closed
// past each other; the contact models never saw them there (the proxies stayed on the cloth).
TEST(PinchStallTest, TheModelsNeverSeeFingersThatPassedThroughTheCloth) {
  InProcessSystem system(PinchScene(), LinkImpairments{});
  system.AddStall(Stall{StallTarget::kDeviceBridge, kStallAt_s, 0.030});
  system.RunUntil(kStallAt_s);
  const double held_gap_m = (system.finger(0).position_m - system.finger(1).position_m).norm();
  double smallest_device_gap_m = held_gap_m, smallest_model_gap_m = held_gap_m;
  while (system.t_s() < kStallAt_s + 0.2) {
    system.Step();
    smallest_device_gap_m =
        std::min(smallest_device_gap_m, system.finger(0).position_m.y() - system.finger(1).position_m.y());
    const device::DeviceBridge& bridge = system.bridge().bridge();
    smallest_model_gap_m = std::min(smallest_model_gap_m, bridge.model_finger_state(device::Manipulator::kThumb).p_W_m.y() -
                                                              bridge.model_finger_state(device::Manipulator::kIndex).p_W_m.y());
  }
  std::cout << "[measured] fingers " << held_gap_m * 1e3 << " mm apart when held; closest " << smallest_device_gap_m * 1e3
            << " mm on the device, " << smallest_model_gap_m * 1e3 << " mm in the models\n";
  ASSERT_LT(smallest_device_gap_m, 0.0) << "the fingers did not pass each other: the test would prove nothing";
  EXPECT_GT(smallest_model_gap_m, held_gap_m - 0.0005);
  const device::BridgeCounters& c = system.bridge().bridge().counters();
  EXPECT_EQ(c.held_cuts_by_cause[static_cast<std::size_t>(device::CutCause::kBridgeStall)], 2u) << "one per finger";
  EXPECT_EQ(c.contacts_ended, 0u);
}

// Longer than the safety stage's resume_within_s: the contact ends (zero force, counted), and the
// force comes back over the start-up ramp, never above what the squeeze held.
TEST(PinchStallTest, ALongPauseEndsTheContactAtZeroAndCountsIt) {
  InProcessSystem system(PinchScene(), LinkImpairments{});
  system.AddStall(Stall{StallTarget::kDeviceBridge, kStallAt_s, 0.100});
  system.RunUntil(kStallAt_s);
  const double held_N = system.finger(0).commanded_N.norm();
  double peak_N = 0.0;
  bool zero_seen = false;
  while (system.t_s() < kStallAt_s + 1.0) {
    system.Step();
    peak_N = std::max(peak_N, system.finger(0).commanded_N.norm());
    zero_seen = zero_seen || system.finger(0).commanded_N.isZero(0.0);
  }
  EXPECT_TRUE(zero_seen);
  EXPECT_LE(peak_N, ResumeBoundN(held_N));
  const device::BridgeCounters& c = system.bridge().bridge().counters();
  EXPECT_EQ(c.contacts_ended, 2u);
  EXPECT_EQ(system.bridge().bridge().resumes_finished(), 2u);
  EXPECT_TRUE(system.bridge().bridge().resumes()[0].ended);
}

TEST(PinchStallTest, StallsAreExactlyRepeatable) {
  const Stall stall{StallTarget::kLocalContact, kStallAt_s, 0.020};
  StallResponseOptions options;
  options.watch_after_s = 0.2;
  const StallResponse a = MeasureStall(PinchScene(), stall, options), b = MeasureStall(PinchScene(), stall, options);
  EXPECT_EQ(a.fingers[0].peak_after_N, b.fingers[0].peak_after_N);
  EXPECT_EQ(a.held_again_after_s, b.held_again_after_s);
}

TEST(InProcessSystemStallTest, RefusesANegativeOrNonFiniteStall) {
  InProcessSystem system(PinchScene(), LinkImpairments{});
  EXPECT_THROW(system.AddStall(Stall{StallTarget::kAll, -1.0, 0.01}), std::invalid_argument);
  EXPECT_THROW(system.AddStall(Stall{StallTarget::kAll, 1.0, std::numeric_limits<double>::quiet_NaN()}),
               std::invalid_argument);
}

}  // namespace
}  // namespace haptex::in_process
