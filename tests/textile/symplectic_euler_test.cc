#include "libs/textile/symplectic_euler.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_material.h"
#include "tests/support/allocation_counter.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

FabricModel SoftModel(int n) {
  return BuildFabricModel(MaterialFromKes(testing::LoadDatabaseFabric("wang2011_navy_sparkle_sweat")),
                          {0.2, 0.2, n, n});
}

FabricState HangingState(const FabricModel& model) {
  Placement pl;
  pl.axis_u_W = Eigen::Vector3d(0, 0, -1);
  pl.axis_v_W = Eigen::Vector3d(1, 0, 0);
  FabricState s = MakeRestState(model, pl);
  for (int p : testing::WarpRow(model, 0)) s.Fix(p);
  return s;
}

TEST(SymplecticEulerTest, RefusesUnstableSubsteps) {
  const FabricModel model = SoftModel(11);
  StepOptions opt;
  opt.method = Integrator::kSymplecticEuler;
  opt.dt_s = 0.01;
  const int needed = SymplecticSubsteps(model, opt);
  EXPECT_GE(needed, 1);
  EXPECT_NEAR(opt.dt_s / needed, EstimateExplicitStableStep(model), EstimateExplicitStableStep(model));
  if (needed > 1) {
    opt.substeps = needed - 1;
    try {
      FabricStepper stepper(model, opt);
      ADD_FAILURE() << "expected a refusal";
    } catch (const std::invalid_argument& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr("unstable"));
    }
  }
  opt.substeps = 0;
  opt.max_substeps = 1;
  opt.dt_s = 1.0;
  EXPECT_THROW(FabricStepper(model, opt), std::invalid_argument);
}

TEST(SymplecticEulerTest, AgreesWithImplicitEulerAtSmallSteps) {
  const FabricModel model = SoftModel(7);
  FabricState a = HangingState(model), b = a;
  StepOptions implicit;
  implicit.dt_s = 1e-4;
  implicit.cg_tolerance = 1e-8;
  StepOptions cheap = implicit;
  cheap.method = Integrator::kSymplecticEuler;
  FabricStepper sa(model, implicit), sb(model, cheap);
  for (int i = 0; i < 1000; ++i) {  // 0.1 s of falling and swinging
    sa.Step(&a);
    sb.Step(&b);
  }
  const int tip = model.mesh.Index(6, 3);
  const double travel = (a.x(tip) - MakeRestState(model).x(tip)).norm();
  EXPECT_GT(travel, 1e-3);
  // Both first order: they agree to a few percent of the motion.
  EXPECT_LT((a.x(tip) - b.x(tip)).norm(), 0.05 * travel + 1e-4);
  EXPECT_EQ(b.diagnostics.nan_events, 0);
}

TEST(SymplecticEulerTest, WarmedUpStepDoesNotAllocate) {
  if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting off";
  const FabricModel model = SoftModel(11);
  FabricState s = HangingState(model);
  StepOptions opt;
  opt.method = Integrator::kSymplecticEuler;
  opt.dt_s = 0.001;
  FabricStepper stepper(model, opt);
  stepper.Step(&s);
  haptex::testing::AllocationCounter counter;
  for (int i = 0; i < 3; ++i) stepper.Step(&s);
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::textile
