#include "libs/textile/implicit_euler.h"

#include <gtest/gtest.h>

#include "libs/textile/external_force.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_material.h"
#include "tests/support/allocation_counter.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

class ImplicitEulerTest : public ::testing::Test {
 protected:
  FabricModel MakeModel(int n) {
    ModelOptions o;
    return BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.2, 0.2, n, n}, o);
  }
  // Hanging from the stand: warp downwards, the row u = 0 fixed at the top.
  static FabricState Hanging(const FabricModel& model) {
    Placement pl;
    pl.axis_u_W = Eigen::Vector3d(0, 0, -1);
    pl.axis_v_W = Eigen::Vector3d(1, 0, 0);
    FabricState s = MakeRestState(model, pl);
    for (int p : testing::WarpRow(model, 0)) s.Fix(p);
    return s;
  }
};

TEST_F(ImplicitEulerTest, FreeFallIsExactInVelocity) {
  ModelOptions o;
  o.drag.linear_N_s_per_m3 = 0.0;
  o.drag.quadratic_coefficient = 0.0;
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 5, 5}, o);
  FabricState s = MakeRestState(model);
  StepOptions opt;
  opt.dt_s = 0.01;
  opt.cg_tolerance = 1e-10;
  FabricStepper stepper(model, opt);
  for (int i = 0; i < 10; ++i) stepper.Step(&s);
  for (int p = 0; p < model.num_particles; ++p) {
    EXPECT_NEAR(s.v(p).z(), -9.81 * 0.1, 1e-9);
    // Backward Euler position: sum of h * v_k = h^2 g (1 + ... + 10).
    EXPECT_NEAR(s.x(p).z(), -9.81 * 0.01 * 0.01 * 55, 1e-9);
  }
  EXPECT_NEAR(s.time_s, 0.1, 1e-12);
}

TEST_F(ImplicitEulerTest, FixedAndPrescribedParticlesFollowExactly) {
  const FabricModel model = MakeModel(9);
  FabricState s = Hanging(model);
  const int moving = model.mesh.Index(8, 4);
  s.Prescribe(moving, Eigen::Vector3d(0.1, 0.0, 0.0));
  const Eigen::Vector3d start = s.x(moving);
  const auto top = testing::WarpRow(model, 0);
  const FabricState initial = s;
  StepOptions opt;
  opt.dt_s = 0.005;
  FabricStepper stepper(model, opt);
  for (int i = 0; i < 40; ++i) stepper.Step(&s);
  for (int p : top) EXPECT_EQ(s.x(p), initial.x(p));
  EXPECT_NEAR((s.x(moving) - (start + Eigen::Vector3d(0.1 * 0.2, 0, 0))).norm(), 0.0, 1e-12);
  // The rest of the fabric moved (it fell and was dragged).
  EXPECT_GT((s.x(model.mesh.Index(4, 4)) - initial.x(model.mesh.Index(4, 4))).norm(), 1e-4);
}

TEST_F(ImplicitEulerTest, HangingFabricSettlesWithConvergedCg) {
  const FabricModel model = MakeModel(11);
  FabricState s = Hanging(model);
  StepOptions opt;
  opt.dt_s = 0.01;
  FabricStepper stepper(model, opt);
  const int steps = testing::RunToRest(&stepper, &s, 2000, 1e-4);
  EXPECT_LT(steps, 2000);
  EXPECT_EQ(s.diagnostics.nan_events, 0);
  EXPECT_EQ(s.diagnostics.cg_not_converged, 0);
  // Everything below the stand.
  for (int p = 0; p < model.num_particles; ++p) EXPECT_LE(s.x(p).z(), 1e-9);
}

TEST_F(ImplicitEulerTest, FullyFixedFabricStepsWithoutIterating) {
  // No free particle: a zero right-hand side, which CG does not iterate on (Gauss-Seidel's start
  // then computes only its reference size).
  const FabricModel model = MakeModel(9);
  FabricState s = Hanging(model);
  for (int p = 0; p < model.num_particles; ++p) s.Fix(p);
  const FabricState initial = s;
  StepOptions opt;
  opt.preconditioner = Preconditioner::kGaussSeidel;
  FabricStepper stepper(model, opt);
  for (int i = 0; i < 3; ++i) {
    const CgReport report = stepper.Step(&s).cg;
    EXPECT_EQ(report.iterations, 0);
    EXPECT_TRUE(report.converged);
    EXPECT_TRUE(report.finite);
  }
  EXPECT_EQ(s.x_W_m, initial.x_W_m);
  EXPECT_EQ(s.diagnostics.nan_events, 0);
}

TEST_F(ImplicitEulerTest, WarmedUpStepDoesNotAllocate) {
  if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting off";
  const FabricModel model = MakeModel(21);
  FabricState s = Hanging(model);
  SetPointLoad(model.mesh.Index(20, 10), Eigen::Vector3d(0, 1.0, 0), &s);
  StepOptions opt;
  FabricStepper stepper(model, opt);
  for (int i = 0; i < 3; ++i) stepper.Step(&s);
  haptex::testing::AllocationCounter counter;
  for (int i = 0; i < 5; ++i) stepper.Step(&s);
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::textile
