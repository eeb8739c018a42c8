// Pauses of the host against a held pinch, deterministically (services/in_process, the stall
// injector on the simulated clock): whatever pauses, for up to 30 ms, the force after the cut stays
// within the resume bound, the pinch holds again within 100 ms, and longer pauses end the contact
// at zero force, counted.
#include "services/in_process/stall_response.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>
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

INSTANTIATE_TEST_SUITE_P(Pauses, PinchStallTest,
                         ::testing::Values(StallCase{"device_bridge_5ms", StallTarget::kDeviceBridge, 5.0},
                                           StallCase{"device_bridge_10ms", StallTarget::kDeviceBridge, 10.0},
                                           StallCase{"device_bridge_30ms", StallTarget::kDeviceBridge, 30.0},
                                           StallCase{"local_contact_10ms", StallTarget::kLocalContact, 10.0},
                                           StallCase{"local_contact_30ms", StallTarget::kLocalContact, 30.0},
                                           StallCase{"global_sim_30ms", StallTarget::kGlobalSim, 30.0},
                                           StallCase{"mock_grab_30ms", StallTarget::kMockGrab, 30.0},
                                           StallCase{"all_10ms", StallTarget::kAll, 10.0},
                                           StallCase{"all_30ms", StallTarget::kAll, 30.0}),
                         [](const ::testing::TestParamInfo<StallCase>& param) {
                           return std::string(param.param.name);
                         });

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
    smallest_model_gap_m =
        std::min(smallest_model_gap_m, bridge.model_finger_state(device::Manipulator::kThumb).p_W_m.y() -
                                           bridge.model_finger_state(device::Manipulator::kIndex).p_W_m.y());
  }
  std::cout << "[measured] fingers " << held_gap_m * 1e3 << " mm apart when held; closest "
            << smallest_device_gap_m * 1e3 << " mm on the device, " << smallest_model_gap_m * 1e3
            << " mm in the models\n";
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
  system.AddStall(Stall{StallTarget::kDeviceBridge, kStallAt_s, 0.150});
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

// A contact service that stops (killed, or stopped for good): the bridge's watchdog takes the force
// away 20 ms after its last model (10 ms fresh, 10 ms ramp), and it stays away.
TEST(PinchStallTest, AStoppedContactServiceTakesTheForceAwayWithinTheModelLifetime) {
  InProcessSystem system(PinchScene(), LinkImpairments{});
  system.AddStall(Stall{StallTarget::kLocalContact, kStallAt_s, 1.0});
  system.RunUntil(kStallAt_s);
  ASSERT_GT(system.finger(0).commanded_N.norm(), 3.0) << "not squeezing: the test would prove nothing";
  // the last model left local_contact at the stall's start; the mock takes the command a tick later
  const double zero_by_s = kStallAt_s + device::kMaxForceModelSilence_s + 2 * system.dt_s();
  double first_zero_s = -1.0;
  while (system.t_s() < kStallAt_s + 1.0) {
    system.Step();
    const bool zero = system.finger(0).commanded_N.isZero(0.0) && system.finger(1).commanded_N.isZero(0.0);
    if (zero && first_zero_s < 0.0) first_zero_s = system.t_s();
    if (system.t_s() >= zero_by_s) {
      ASSERT_TRUE(zero) << "force at " << system.t_s() << " s";
    }
  }
  std::cout << "[measured] force zero " << (first_zero_s - kStallAt_s) * 1e3 << " ms after the last model\n";
}

// A bridge that stops: the controller's host timeout takes the force away 5 ms after the last
// command, and it stays away.
TEST(PinchStallTest, AStoppedBridgeLeavesTheDeviceAtZeroWithinTheHostTimeout) {
  InProcessSystem system(PinchScene(), LinkImpairments{});
  system.AddStall(Stall{StallTarget::kDeviceBridge, kStallAt_s, 1.0});
  system.RunUntil(kStallAt_s);
  ASSERT_GT(system.finger(0).commanded_N.norm(), 3.0) << "not squeezing: the test would prove nothing";
  const double zero_by_s = kStallAt_s + device::MockControllerConfig{}.host_timeout_s + system.dt_s();
  while (system.t_s() < kStallAt_s + 1.0) {
    system.Step();
    if (system.t_s() >= zero_by_s) {
      ASSERT_TRUE(system.finger(0).commanded_N.isZero(0.0) && system.finger(1).commanded_N.isZero(0.0))
          << "force at " << system.t_s() << " s";
    }
  }
}

// The fold (launch/scenes/fold.textproto): the pinch holds through the fold, the index alone then
// holds the folded fabric, and the run ends at zero force.
TEST(FoldInProcessTest, PinchHeldThroughTheFoldThenOneFinger) {
  static const scene::LoadedScene fold =
      scene::LoadScene(haptex::testing::SourceDir() + "/launch/scenes/fold.textproto",
                       scene::FabricDatabase(haptex::testing::SourceDir() + "/data/fabrics"));
  InProcessSystem system(fold, LinkImpairments{});
  double peak_N = 0.0;
  while (system.t_s() < fold.scene.duration_s()) {
    system.Step();
    peak_N = std::max({peak_N, system.finger(0).commanded_N.norm(), system.finger(1).commanded_N.norm()});
  }
  const auto& ticks = system.local_contact().counters().state_ticks;
  const auto count = [&](contact::ContactState s) { return ticks[static_cast<std::size_t>(s) - 1]; };
  const std::uint64_t pinched = count(contact::ContactState::kVIII) + count(contact::ContactState::kIX);
  const std::uint64_t one_finger = count(contact::ContactState::kIV) + count(contact::ContactState::kV);
  std::cout << "[measured] fold: pinched " << pinched << " ticks, one finger " << one_finger << ", peak " << peak_N
            << " N\n";
  // 1 kHz ticks: the fold and its hold take about 1.9 s; the let-go's hold 0.5 s and more
  EXPECT_GT(pinched, 1500u);
  EXPECT_GT(one_finger, 500u);
  EXPECT_LT(peak_N, 10.0);
}

// A pause of local_contact too short for any cut, while the thumb and index hold the fold: the
// global step that missed the patch's result holds the patch interior where the last result put
// it. Relaxed instead, the next patch answered the resting fingers with twice the force they held.
TEST(FoldInProcessTest, AShortPauseOfTheContactServiceIsNoJolt) {
  static const scene::LoadedScene fold =
      scene::LoadScene(haptex::testing::SourceDir() + "/launch/scenes/fold.textproto",
                       scene::FabricDatabase(haptex::testing::SourceDir() + "/data/fabrics"));
  for (const double pause_ms : {2.0, 5.0}) {
    StallResponseOptions options;
    options.watch_after_s = 0.2;
    const StallResponse r = MeasureStall(fold, Stall{StallTarget::kLocalContact, 5.5, pause_ms / 1e3}, options);
    ASSERT_TRUE(r.pinched_before) << "not holding the fold when the stall began: the test would prove nothing";
    for (const FingerStallResponse& f : r.fingers) {
      ASSERT_GT(f.held_N, 1.0);
      EXPECT_LE(f.peak_after_N, ResumeBoundN(f.held_N)) << pause_ms << " ms";
    }
  }
}

// Two stalls of the bridge 110 ms apart over a 100 ms round trip with 5 % loss (the second while
// the first one's resume is settling): a finger back on its surface still moves with the return,
// and extrapolated a round trip ahead it left the pinch in the model; the model's force fell to
// zero, the resume ended, and the squeeze closed the fingers past each other (11.6 N, a buzz).
TEST(PinchStallTest, ASecondStallOverASlowLinkKeepsThePinch) {
  netsim::ImpairmentConfig each_way;
  each_way.delay_ms = 50.0;
  each_way.jitter_ms = 1.0;
  each_way.loss = 0.05;
  InProcessSystem system(PinchScene(), LinkImpairments::HapticLink(each_way, 3));
  system.AddStall(Stall{StallTarget::kDeviceBridge, 10.69, 0.010});
  system.AddStall(Stall{StallTarget::kDeviceBridge, 10.80, 0.035});
  system.RunUntil(10.6);
  double peak_N = 0.0;
  bool crossed_in_model = false;
  const device::DeviceBridge& bridge = system.bridge().bridge();
  while (system.t_s() < 11.2) {
    system.Step();
    peak_N = std::max({peak_N, system.finger(0).commanded_N.norm(), system.finger(1).commanded_N.norm()});
    // the squeeze closes the real fingers past each other while the force is cut; the models
    // must never see that (the thumb is at +y)
    const device::FingerState& thumb = bridge.model_finger_state(device::Manipulator::kThumb);
    const device::FingerState& index = bridge.model_finger_state(device::Manipulator::kIndex);
    for (const Eigen::Vector3d* t : {&thumb.p_W_m, &thumb.p_link_pred_W_m}) {
      for (const Eigen::Vector3d* i : {&index.p_W_m, &index.p_link_pred_W_m}) crossed_in_model |= t->y() < i->y();
    }
  }
  const device::BridgeCounters& c = bridge.counters();
  std::cout << "[measured] two bridge stalls over a 100 ms link: peak " << peak_N << " N\n";
  EXPECT_GE(c.held_cuts_by_cause[static_cast<std::size_t>(device::CutCause::kBridgeStall)], 2u);
  EXPECT_LE(peak_N, ResumeBoundN(4.91) + 0.05) << "the pinch held 4.91 N";
  EXPECT_FALSE(crossed_in_model) << "the models saw the fingers past each other";
  const int situation = static_cast<int>(system.local_contact().contact_state());
  EXPECT_TRUE(situation == static_cast<int>(contact::ContactState::kVIII) ||
              situation == static_cast<int>(contact::ContactState::kIX))
      << "pinch lost: state " << situation;
}

TEST(PinchStallTest, StallsAreExactlyRepeatable) {
  const Stall stall{StallTarget::kLocalContact, kStallAt_s, 0.020};
  StallResponseOptions options;
  options.watch_after_s = 0.2;
  const StallResponse a = MeasureStall(PinchScene(), stall, options), b = MeasureStall(PinchScene(), stall, options);
  EXPECT_EQ(a.fingers[0].peak_after_N, b.fingers[0].peak_after_N);
  EXPECT_EQ(a.held_again_after_s, b.held_again_after_s);
}

// A scene's stalls pause the services in process as `haptex launch` pauses their processes.
TEST(InProcessSystemStallTest, TheScenesStallsArePlayed) {
  std::ifstream file(haptex::testing::SourceDir() + "/launch/scenes/pinch_stretch.textproto");
  std::stringstream text;
  text << file.rdbuf() << "stalls { service: SERVICE_DEVICE_BRIDGE at_s: 4.5 duration_s: 0.03 }\n";
  const scene::LoadedScene scene = scene::ParseScene(
      text.str(), "pinch_stretch_stalled", scene::FabricDatabase(haptex::testing::SourceDir() + "/data/fabrics"));
  InProcessSystem system(scene, LinkImpairments{});
  system.RunUntil(4.7);
  const device::BridgeCounters& c = system.bridge().bridge().counters();
  EXPECT_EQ(c.held_cuts_by_cause[static_cast<std::size_t>(device::CutCause::kBridgeStall)], 2u);
  EXPECT_EQ(system.mock().controller().counters().host_timeouts, 1u);
}

TEST(InProcessSystemStallTest, RefusesANegativeOrNonFiniteStall) {
  InProcessSystem system(PinchScene(), LinkImpairments{});
  EXPECT_THROW(system.AddStall(Stall{StallTarget::kAll, -1.0, 0.01}), std::invalid_argument);
  EXPECT_THROW(system.AddStall(Stall{StallTarget::kAll, 1.0, std::numeric_limits<double>::quiet_NaN()}),
               std::invalid_argument);
}

}  // namespace
}  // namespace haptex::in_process
