#include "libs/textile/fabric_stepper.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "libs/textile/external_force.h"
#include "libs/textile/fabric_strain.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/validation.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

class FabricStepperTest : public ::testing::Test {
 protected:
  FabricModel model_ = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 6, 6});
};

TEST_F(FabricStepperTest, InvalidOptionsThrowAtConfiguration) {
  auto expect_throw = [&](StepOptions o, const char* text) {
    try {
      FabricStepper dut(model_, o);
      ADD_FAILURE() << "expected an exception mentioning " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(text));
    }
  };
  StepOptions o;
  o.dt_s = 0.0;
  expect_throw(o, "dt_s");
  o.dt_s = -1.0;
  expect_throw(o, "dt_s");
  o.dt_s = std::numeric_limits<double>::quiet_NaN();
  expect_throw(o, "dt_s");
  o = {};
  o.cg_tolerance = 0.0;
  expect_throw(o, "cg_tolerance");
  o = {};
  o.cg_max_iterations = 0;
  expect_throw(o, "cg_max_iterations");
  o = {};
  o.max_speed_m_per_s = -1.0;
  expect_throw(o, "max_speed_m_per_s");
  o = {};
  o.newton_max_iterations = 0;
  expect_throw(o, "newton_max_iterations");
  o = {};
  o.newton_tolerance = 1.0;
  expect_throw(o, "newton_tolerance");
  o = {};
  o.max_step_halvings = -1;
  expect_throw(o, "max_step_halvings");
  o.max_step_halvings = kMaxStepHalvings + 1;
  expect_throw(o, "max_step_halvings");
  o = {};
  o.max_strain_rise_per_step = std::numeric_limits<double>::infinity();
  expect_throw(o, "max_strain_rise_per_step");
  o = {};
  o.method = Integrator::kBdf2;  // with one linearised step
  expect_throw(o, "kBdf2");
}

TEST_F(FabricStepperTest, NanIsRolledBackAndCounted) {
  FabricState s = MakeRestState(model_);
  FabricStepper dut(model_, {});
  dut.Step(&s);
  const FabricState good = s;
  SetPointLoad(3, Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 0, 0), &s);
  const StepResult r = dut.Step(&s);
  EXPECT_EQ(r.status, StepStatus::kNanRecovered);
  EXPECT_EQ(s.diagnostics.nan_events, 1);
  EXPECT_TRUE(s.x_W_m.allFinite());
  EXPECT_EQ(s.x_W_m, good.x_W_m);
  EXPECT_EQ(s.v_W_m_per_s.norm(), 0.0);
  EXPECT_STREQ(ToString(r.status), "nan_recovered");
}

TEST_F(FabricStepperTest, SpeedsAreCappedAndCounted) {
  FabricState s = MakeRestState(model_);
  StepOptions o;
  o.max_speed_m_per_s = 0.5;
  FabricStepper dut(model_, o);
  SetPointLoad(0, Eigen::Vector3d(0, 0, 50.0), &s);
  const StepResult r = dut.Step(&s);
  EXPECT_EQ(r.status, StepStatus::kSpeedCapped);
  EXPECT_GT(r.capped_particles, 0);
  EXPECT_LE(MaxSpeed(s), 0.5 + 1e-12);
  EXPECT_EQ(s.diagnostics.speed_capped, 1);
}

TEST_F(FabricStepperTest, CgIterationLimitIsReported) {
  FabricState s = MakeRestState(model_);
  StepOptions o;
  o.newton_max_iterations = 1;
  o.cg_max_iterations = 1;
  o.cg_tolerance = 1e-12;
  o.max_step_halvings = 0;  // one solve: the guard would retake this load's step in parts
  FabricStepper dut(model_, o);
  SetPointLoad(7, Eigen::Vector3d(0, 0, 1.0), &s);
  const StepResult r = dut.Step(&s);
  EXPECT_EQ(r.status, StepStatus::kCgNotConverged);
  EXPECT_EQ(s.diagnostics.cg_not_converged, 1);
  EXPECT_EQ(r.cg.iterations, 1);
}

// The hanging cloth, shaken (start_) or pulled at its bottom edge.
class StepSplittingTest : public ::testing::Test {
 protected:
  StepSplittingTest() : model_(BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.2, 0.2, 11, 11})) {
    start_ = PulledAtRest(Eigen::Vector3d::Zero());
    validation::Perturb(&start_, 0.001, 0.2, 3);
  }
  // The hanging cloth at rest with `load_W_N` on each particle of its bottom edge.
  FabricState PulledAtRest(const Eigen::Vector3d& load_W_N) const {
    Placement hanging;
    hanging.axis_u_W = Eigen::Vector3d(0, 0, -1);
    hanging.axis_v_W = Eigen::Vector3d(1, 0, 0);
    FabricState s = MakeRestState(model_, hanging);
    for (int p : testing::WarpRow(model_, 0)) s.Fix(p);
    for (int p : testing::WarpRow(model_, 10)) SetPointLoad(p, load_W_N, &s);
    return s;
  }
  FabricModel model_;
  FabricState start_;
};

// Newton cannot meet the tolerance: the step is retaken in halves down to the limit, the rest
// of the step at that size, it still covers dt, and every event is counted.
TEST_F(StepSplittingTest, AStepThatDoesNotConvergeIsHalvedToTheLimitAndCounted) {
  StepOptions o;
  o.dt_s = 0.05;
  o.newton_max_iterations = 2;
  o.newton_tolerance = 1e-13;
  o.max_step_halvings = 3;
  FabricStepper dut(model_, o);
  FabricState s = start_;
  const StepResult r = dut.Step(&s);
  EXPECT_EQ(r.step_halvings, 3);
  EXPECT_EQ(dut.substeps(), 8);
  EXPECT_EQ(s.diagnostics.step_halvings, 3);
  EXPECT_FALSE(r.newton_converged);
  EXPECT_EQ(s.diagnostics.newton_not_converged, 1);
  EXPECT_EQ(r.newton_iterations, 3 * 2 + 8 * 2) << "every solve counts, the retaken sub-steps' too";
  EXPECT_NEAR(s.time_s, start_.time_s + 0.05, 1e-15);
  EXPECT_TRUE(s.x_W_m.allFinite());
}

// The hanging cloth pulled down hard at its bottom edge from rest: at 50 ms the linearised step
// overshoots by orders of magnitude (the tensile law's slope jumps at zero strain) and Newton's
// iterations cannot bring it back; halved down to 0.8 ms the residual is small. (Newton's rate is
// linear, about 3x per iteration, even there: docs/fabric-model.md "Accuracy in motion".)
TEST_F(StepSplittingTest, HalvingTakesTheResidualDownWhereTheWholeStepCannot) {
  const FabricState start = PulledAtRest(Eigen::Vector3d(0.5, 0.3, -2.0));
  StepOptions o;
  o.dt_s = 0.05;
  o.newton_max_iterations = 8;
  o.newton_tolerance = 1e-6;
  o.max_step_halvings = 0;
  FabricStepper whole(model_, o);
  FabricState a = start;
  const StepResult ra = whole.Step(&a);
  o.max_step_halvings = 6;
  FabricStepper halved(model_, o);
  FabricState b = start;
  const StepResult rb = halved.Step(&b);
  std::cout << "[measured] 50 ms pulled hard, 8 iterations: residual " << ra.newton_relative_residual << " whole, "
            << rb.newton_relative_residual << " in " << (1 << rb.step_halvings) << " parts\n";
  EXPECT_FALSE(ra.newton_converged);
  EXPECT_EQ(ra.step_halvings, 0);
  EXPECT_EQ(rb.step_halvings, 6);
  EXPECT_EQ(halved.substeps(), 64);
  EXPECT_LT(rb.newton_relative_residual, 1e-3 * ra.newton_relative_residual);
  EXPECT_NEAR(b.time_s, start.time_s + 0.05, 1e-12);
  EXPECT_EQ(b.diagnostics.step_halvings, 6);
  EXPECT_EQ(b.diagnostics.newton_not_converged, 1);
}

// The strain bound: a step whose largest strain rises by more than the bound is split; without
// the bound the same step is not. The hanging cloth at rest is pulled down at its bottom edge.
TEST_F(StepSplittingTest, AStrainRiseBeyondTheBoundSplitsTheStep) {
  const FabricState pulled = PulledAtRest(Eigen::Vector3d(0, 0, -2.0));
  StepOptions o;
  o.dt_s = 0.02;
  o.newton_max_iterations = 10;
  o.max_step_halvings = 4;
  o.max_strain_rise_per_step = 0.0;
  FabricStepper unbounded(model_, o);
  FabricState a = pulled;
  const StepResult ra = unbounded.Step(&a);
  const double rise = LargestTensileStrain(model_, a.x_W_m) - LargestTensileStrain(model_, pulled.x_W_m);
  ASSERT_GT(rise, 0.0);
  EXPECT_EQ(ra.step_halvings, 0);
  o.max_strain_rise_per_step = 0.3 * rise;
  FabricStepper bounded(model_, o);
  FabricState b = pulled;
  const StepResult rb = bounded.Step(&b);
  EXPECT_GT(rb.step_halvings, 0);
  EXPECT_EQ(b.diagnostics.step_halvings, rb.step_halvings);
  EXPECT_NEAR(b.time_s, pulled.time_s + 0.02, 1e-15);
}

// The default step guards the cloth against its own linearisation: a point load of 1 N on one
// particle of the hanging denim, from rest. One linearised step at 10 ms, linearised where the
// cloth is soft, stretched a triangle at the load 900 times further than a converged step (18.5
// against 0.020); the default retakes such steps in parts and came within 1.7 times (0.034).
TEST_F(StepSplittingTest, TheDefaultStepGuardsAPointLoadAgainstTheLinearisationsOvershoot) {
  FabricState at_rest = PulledAtRest(Eigen::Vector3d::Zero());
  const int centre = model_.mesh.Index(5, 5);
  SetPointLoad(centre, Eigen::Vector3d(0, 1.0, 0), &at_rest);
  auto peak_strain = [&](const StepOptions& o, FabricState* s) {
    FabricStepper stepper(model_, o);
    double peak = 0.0;
    for (int i = 0; i < 20; ++i) {
      stepper.Step(s);
      peak = std::max(peak, LargestTensileStrain(model_, s->x_W_m));
    }
    return peak;
  };
  StepOptions unguarded;
  unguarded.max_step_halvings = 0;
  StepOptions converged;
  converged.dt_s = 0.01 / 16.0;
  converged.newton_max_iterations = 30;
  converged.newton_tolerance = 1e-6;
  converged.cg_tolerance = 1e-6;
  converged.max_step_halvings = 0;
  FabricState a = at_rest, b = at_rest, c = at_rest;
  const double unguarded_peak = peak_strain(unguarded, &a);
  const double guarded_peak = peak_strain(StepOptions{}, &b);
  FabricStepper fine(model_, converged);
  double converged_peak = 0.0;
  for (int i = 0; i < 20 * 16; ++i) {
    fine.Step(&c);
    converged_peak = std::max(converged_peak, LargestTensileStrain(model_, c.x_W_m));
  }
  std::cout << "[measured] 1 N on one particle, peak strain: one linearised step " << unguarded_peak << ", default "
            << guarded_peak << " (" << b.diagnostics.step_halvings << " halvings), converged " << converged_peak
            << "\n";
  EXPECT_GT(unguarded_peak, 10.0 * converged_peak) << "the case no longer shows the overshoot";
  EXPECT_LT(guarded_peak, 2.0 * converged_peak);
  EXPECT_GT(guarded_peak, 0.8 * converged_peak);
  EXPECT_GT(b.diagnostics.step_halvings, 0);
  EXPECT_EQ(a.diagnostics.step_halvings, 0);
}

// BDF2 on a problem with a closed form: every particle of a flat cloth on a spring to where it
// rests, stiffness proportional to its mass, no gravity, drag or damping, let go 1 mm out of
// plane. The cloth moves as a whole (no strain, no bending), so each particle is a harmonic
// oscillator of the same period: z(t) = A cos(w t).
class Bdf2Test : public ::testing::Test {
 protected:
  static constexpr double kOmega_rad_per_s = 2.0 * 3.14159265358979323846 * 5.0;  // 5 Hz
  static constexpr double kAmplitude_m = 0.001;
  static ModelOptions Undamped() {
    ModelOptions o;
    o.gravity_m_per_s2.setZero();
    o.drag.linear_N_s_per_m3 = 0.0;
    o.drag.quadratic_coefficient = 0.0;
    o.damping = {0.0, 0.0, 0.0};
    return o;
  }
  Bdf2Test()
      : model_(BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 6, 6}, Undamped())),
        rest_(MakeRestState(model_)) {
    for (int p = 0; p < model_.num_particles; ++p) {
      rest_.anchor_stiffness_N_per_m[p] = kOmega_rad_per_s * kOmega_rad_per_s * model_.mass_kg[p];
      rest_.anchor_W_m.segment<3>(3 * p) = rest_.x(p);
    }
  }
  // The largest |z - A cos(w t)| over `periods` periods with steps of dt_s.
  double LargestError(Integrator method, double dt_s, double periods) const {
    StepOptions o;
    o.method = method;
    o.newton_max_iterations = 8;
    o.newton_tolerance = 1e-8;
    o.dt_s = dt_s;
    o.cg_tolerance = 1e-10;
    FabricStepper dut(model_, o);
    FabricState s = rest_;
    for (int p = 0; p < model_.num_particles; ++p) s.x_W_m[3 * p + 2] += kAmplitude_m;
    double worst = 0.0;
    const int steps = static_cast<int>(std::lround(periods * 2.0 * 3.14159265358979323846 / kOmega_rad_per_s / dt_s));
    for (int k = 1; k <= steps; ++k) {
      dut.Step(&s);
      const double exact = kAmplitude_m * std::cos(kOmega_rad_per_s * s.time_s);
      for (int p = 0; p < model_.num_particles; ++p) worst = std::max(worst, std::abs(s.x_W_m[3 * p + 2] - exact));
    }
    return worst;
  }
  FabricModel model_;
  FabricState rest_;
};

// Halving the step quarters BDF2's error and halves implicit Euler's; at 40 steps a period BDF2
// is many times closer, where implicit Euler has damped the swing away.
TEST_F(Bdf2Test, SecondOrderAgainstTheClosedForm) {
  const double period_s = 0.2;
  const double bdf2_coarse = LargestError(Integrator::kBdf2, period_s / 40, 2.0);
  const double bdf2_fine = LargestError(Integrator::kBdf2, period_s / 80, 2.0);
  const double euler_coarse = LargestError(Integrator::kImplicitEuler, period_s / 40, 2.0);
  const double euler_fine = LargestError(Integrator::kImplicitEuler, period_s / 80, 2.0);
  std::cout << "[measured] largest error over 2 periods, 40 / 80 steps a period: BDF2 " << bdf2_coarse << " / "
            << bdf2_fine << " m, implicit Euler " << euler_coarse << " / " << euler_fine << " m\n";
  EXPECT_GT(bdf2_coarse / bdf2_fine, 3.3);
  EXPECT_LT(bdf2_coarse / bdf2_fine, 4.7);
  EXPECT_GT(euler_coarse / euler_fine, 1.6);
  EXPECT_LT(euler_coarse / euler_fine, 2.4);
  EXPECT_LT(bdf2_coarse, 0.2 * euler_coarse);
}

// BDF2 remembers the state a step back; a particle its owner moved restarts its history. A
// cloth swinging on its springs, put back at rest where its springs hold it, stays there (its
// remembered swing is forgotten), with or without RestartHistory; a particle moved alone (a
// merge) does not disturb the others' motion.
TEST_F(Bdf2Test, AStateMovedBetweenStepsRestartsItsHistory) {
  StepOptions o;
  o.method = Integrator::kBdf2;
  o.newton_max_iterations = 4;
  o.dt_s = 0.005;
  o.cg_tolerance = 1e-10;
  FabricState swinging = rest_;
  for (int p = 0; p < model_.num_particles; ++p) swinging.x_W_m[3 * p + 2] += kAmplitude_m;
  for (const bool restart : {true, false}) {
    FabricStepper dut(model_, o);
    FabricState s = swinging;
    for (int k = 0; k < 7; ++k) dut.Step(&s);
    ASSERT_GT(s.v_W_m_per_s.norm(), 0.01) << "moving before it is put back";
    s.x_W_m = rest_.x_W_m;
    s.v_W_m_per_s.setZero();
    if (restart) dut.RestartHistory();
    for (int k = 0; k < 5; ++k) {
      dut.Step(&s);
      EXPECT_LT((s.x_W_m - rest_.x_W_m).cwiseAbs().maxCoeff(), 1e-12) << "step " << k << " restart " << restart;
    }
  }
  FabricStepper a(model_, o), b(model_, o);
  FabricState untouched = swinging, moved = swinging;
  for (int k = 0; k < 7; ++k) {
    a.Step(&untouched);
    b.Step(&moved);
  }
  moved.x_W_m[3 * 0 + 2] += 1e-9;  // particle 0 (a corner), a nanometre
  a.Step(&untouched);
  b.Step(&moved);
  const int far = model_.num_particles - 1;  // the opposite corner
  EXPECT_NEAR(moved.x_W_m[3 * far + 2], untouched.x_W_m[3 * far + 2], 1e-10);
}

// Prescribed particles end each step on their path (the extrapolated start is chosen so that
// 2/3 of a step at their velocity ends where a whole step does), and time advances by dt.
TEST_F(Bdf2Test, PrescribedParticlesFollowTheirPathAndTimeAdvancesByTheStep) {
  StepOptions o;
  o.method = Integrator::kBdf2;
  o.newton_max_iterations = 4;
  o.dt_s = 0.01;
  FabricStepper dut(model_, o);
  FabricState s = rest_;
  const Eigen::Vector3d v_W_m_per_s(0.01, -0.02, 0.03);
  s.Prescribe(0, v_W_m_per_s);
  const Eigen::Vector3d start_W_m = s.x(0);
  for (int k = 1; k <= 20; ++k) {
    dut.Step(&s);
    EXPECT_LT((s.x(0) - (start_W_m + k * o.dt_s * v_W_m_per_s)).norm(), 1e-12) << "step " << k;
    EXPECT_NEAR(s.time_s, k * o.dt_s, 1e-12);
  }
}

// A NaN rolls back as for implicit Euler, and the step after starts afresh from rest.
TEST_F(Bdf2Test, NanIsRolledBackAndTheHistoryRestarts) {
  StepOptions o;
  o.method = Integrator::kBdf2;
  o.newton_max_iterations = 4;
  FabricStepper dut(model_, o);
  FabricState s = rest_;
  for (int p = 0; p < model_.num_particles; ++p) s.x_W_m[3 * p + 2] += kAmplitude_m;
  dut.Step(&s);
  dut.Step(&s);
  const Eigen::VectorXd before_W_m = s.x_W_m;
  SetPointLoad(3, Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 0, 0), &s);
  EXPECT_EQ(dut.Step(&s).status, StepStatus::kNanRecovered);
  EXPECT_EQ(s.x_W_m, before_W_m);
  EXPECT_EQ(s.v_W_m_per_s.norm(), 0.0);
  SetPointLoad(3, Eigen::Vector3d::Zero(), &s);
  // from rest at 1 mm minus a little: the springs pull it back, not a stale past's velocity
  FabricState fresh = s;
  FabricStepper reference(model_, o);
  dut.Step(&s);
  reference.Step(&fresh);
  EXPECT_LT((s.x_W_m - fresh.x_W_m).cwiseAbs().maxCoeff(), 1e-12);
}

// Free fall, BDF2: the first step is implicit Euler's (exact in velocity), and BDF2 is exact for
// a velocity linear in time, so the velocity stays exact; the position keeps the first step's
// error of h^2 g / 2, grown to 3/2 of it as the history carries it, and no more.
TEST(Bdf2FreeFallTest, VelocityIsExactAndThePositionErrorDoesNotGrow) {
  ModelOptions o;
  o.drag.linear_N_s_per_m3 = 0.0;
  o.drag.quadratic_coefficient = 0.0;
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 5, 5}, o);
  FabricState s = MakeRestState(model);
  StepOptions opt;
  opt.method = Integrator::kBdf2;
  opt.newton_max_iterations = 4;
  opt.dt_s = 0.01;
  opt.cg_tolerance = 1e-10;
  FabricStepper stepper(model, opt);
  const double g = -9.81, h = opt.dt_s;
  for (int i = 0; i < 20; ++i) stepper.Step(&s);
  for (int p = 0; p < model.num_particles; ++p) {
    EXPECT_NEAR(s.v(p).z(), g * s.time_s, 1e-9);
    const double exact = 0.5 * g * s.time_s * s.time_s;
    EXPECT_NEAR(s.x(p).z() - exact, 1.5 * 0.5 * g * h * h, 1e-3 * std::abs(g) * h * h);
  }
}

}  // namespace
}  // namespace haptex::textile
