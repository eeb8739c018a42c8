#include "libs/textile/fabric_stepper.h"

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

}  // namespace
}  // namespace haptex::textile
