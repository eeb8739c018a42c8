#include "libs/device/passivity_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace haptex::device {
namespace {

constexpr double kTick_s = 2e-4;
constexpr double kStiffness_N_per_m = 1250.0;  // the paper's stiffest cloth response per finger
constexpr double kAmplitude_m = 0.005;
constexpr double kFrequency_Hz = 5.0;

double Position(double t_s) { return kAmplitude_m * std::sin(2.0 * std::numbers::pi * kFrequency_Hz * t_s); }
double Velocity(double t_s) {
  const double w = 2.0 * std::numbers::pi * kFrequency_Hz;
  return kAmplitude_m * w * std::cos(w * t_s);
}

struct Motion {
  double energy_taken_J = 0.0;           ///< sum of -F . dx over the run, with the adjusted force
  double worst_damping_N_s_per_m = 0.0;  ///< largest |adjusted - requested| / |v|
};

// A finger moved back and forth (a person's hand, which the force does not change) against a spring
// the environment renders `delay_s` late, as a model from across a delayed link does.
// `damping_N_s_per_m` adds a damper to the spring.
Motion MoveAgainstDelayedSpring(PassivityController& controller, double delay_s, double duration_s,
                                double damping_N_s_per_m = 0.0) {
  Motion run;
  for (double t = 0.0; t < duration_s; t += kTick_s) {
    const double t_model = std::max(0.0, t - delay_s);
    const Eigen::Vector3d requested(-kStiffness_N_per_m * Position(t_model) - damping_N_s_per_m * Velocity(t_model),
                                    0.0, 0.0);
    const Eigen::Vector3d v(Velocity(t), 0.0, 0.0);
    const Eigen::Vector3d commanded = controller.Adjust(requested, v, kTick_s);
    if (std::abs(v.x()) > 1e-9) {
      run.worst_damping_N_s_per_m = std::max(run.worst_damping_N_s_per_m, (commanded - requested).norm() / v.norm());
    }
    const Eigen::Vector3d dx(Position(t + kTick_s) - Position(t), 0.0, 0.0);
    controller.Observe(commanded, dx);
    run.energy_taken_J -= commanded.dot(dx);
  }
  return run;
}

TEST(PassivityControllerTest, LeavesAPassiveContactAlone) {
  // a sampled spring is passive with a damper above k dt / 2 (Colgate's condition: 0.125 N s/m)
  PassivityController controller(PassivityConfig{});
  const Motion run = MoveAgainstDelayedSpring(controller, 0.0, 10.0, 0.5);
  EXPECT_EQ(controller.counters().damped_steps, 0u);
  EXPECT_EQ(run.worst_damping_N_s_per_m, 0.0);
  EXPECT_GT(run.energy_taken_J, 0.0);
}

TEST(PassivityControllerTest, CatchesTheSampledSpringsOwnLeakOnceItExceedsTheTolerance) {
  // an undamped spring held between samples gives k |dx|^2 / 2 per step: ~1.5 mJ/s here
  PassivityConfig off;
  off.enabled = false;
  PassivityController unprotected(off);
  const double leak_J = -MoveAgainstDelayedSpring(unprotected, 0.0, 10.0).energy_taken_J;
  ASSERT_GT(leak_J, 0.01);
  const PassivityConfig config;
  PassivityController controller(config);
  const Motion run = MoveAgainstDelayedSpring(controller, 0.0, 10.0);
  EXPECT_GT(controller.counters().damped_steps, 0u);
  EXPECT_GE(run.energy_taken_J, -config.deficit_tolerance_J - 1e-4);
  EXPECT_LT(controller.counters().dissipated_J, leak_J) << "it took out more than the leak";
}

TEST(PassivityControllerTest, DampsADelayedSpringUntilItIsPassive) {
  // unprotected, 20 ms of delay makes the spring give the finger energy every cycle
  PassivityConfig off;
  off.enabled = false;
  PassivityController unprotected(off);
  const Motion active = MoveAgainstDelayedSpring(unprotected, 0.020, 2.0);
  ASSERT_LT(active.energy_taken_J, -0.1) << "the delayed spring should be active: the test would prove nothing";

  const PassivityConfig config;
  PassivityController controller(config);
  const Motion run = MoveAgainstDelayedSpring(controller, 0.020, 2.0);
  EXPECT_GT(controller.counters().damped_steps, 0u);
  EXPECT_GT(controller.counters().dissipated_J, 0.1);
  // the finger never received more than the tolerated deficit (plus one step's worth)
  EXPECT_GE(run.energy_taken_J, -config.deficit_tolerance_J - 1e-3);
  EXPECT_GE(controller.energy_J(), -config.deficit_tolerance_J - 1e-3);
  EXPECT_LE(run.worst_damping_N_s_per_m, config.max_damping_N_s_per_m + 1e-9);
}

TEST(PassivityControllerTest, ReserveIsCappedSoOldLossesCannotPayForANewActivePhase) {
  const PassivityConfig config;
  PassivityController controller(config);
  // a long lossy contact: a damper takes energy for 5 s
  for (double t = 0.0; t < 5.0; t += kTick_s) {
    const double v = Velocity(t);
    controller.Observe({-20.0 * v, 0.0, 0.0}, {Position(t + kTick_s) - Position(t), 0.0, 0.0});
  }
  EXPECT_DOUBLE_EQ(controller.energy_J(), config.max_reserve_J);
  // then an active phase is damped as soon as it exceeds the reserve and the tolerance
  const Motion run = MoveAgainstDelayedSpring(controller, 0.020, 4.0);
  EXPECT_GT(controller.counters().damped_steps, 0u);
  EXPECT_GE(run.energy_taken_J, -config.max_reserve_J - config.deficit_tolerance_J - 1e-3);
}

TEST(PassivityControllerTest, ARestingFingerIsNotDamped) {
  PassivityController controller(PassivityConfig{});
  controller.Observe({1.0, 0.0, 0.0}, {0.1, 0.0, 0.0});  // a 0.1 J deficit
  ASSERT_LT(controller.energy_J(), -0.05);
  const Eigen::Vector3d requested(0.5, 0.0, 0.0);
  EXPECT_EQ(controller.Adjust(requested, Eigen::Vector3d::Zero(), kTick_s), requested);
  EXPECT_EQ(controller.Adjust(requested, {std::nan(""), 0.0, 0.0}, kTick_s), requested);
  EXPECT_EQ(controller.counters().damped_steps, 0u);
  // moving, it is damped against its motion, within the limit
  const Eigen::Vector3d adjusted = controller.Adjust(requested, {0.1, 0.0, 0.0}, kTick_s);
  EXPECT_NEAR(adjusted.x(), 0.5 - 50.0 * 0.1, 1e-12);
  controller.Reset();
  EXPECT_EQ(controller.energy_J(), 0.0);
}

TEST(PassivityControllerTest, NonFiniteObservationsAreIgnored) {
  PassivityController controller(PassivityConfig{});
  controller.Observe({std::nan(""), 0.0, 0.0}, {0.001, 0.0, 0.0});
  controller.Observe({1.0, 0.0, 0.0}, {std::numeric_limits<double>::infinity(), 0.0, 0.0});
  EXPECT_EQ(controller.energy_J(), 0.0);
}

TEST(PassivityControllerTest, RefusesConfigurationsThatCannotWork) {
  for (double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    PassivityConfig c;
    c.max_damping_N_s_per_m = bad;
    EXPECT_THROW(PassivityController{c}, std::invalid_argument);
    c = PassivityConfig{};
    c.max_reserve_J = bad;
    EXPECT_THROW(PassivityController{c}, std::invalid_argument);
  }
  PassivityConfig c;
  c.deficit_tolerance_J = -0.001;
  EXPECT_THROW(PassivityController{c}, std::invalid_argument);
}

}  // namespace
}  // namespace haptex::device
