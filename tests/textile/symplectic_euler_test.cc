#include "libs/textile/symplectic_euler.h"

#include <cmath>
#include <cstdio>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "libs/textile/fabric_forces.h"
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

// True explicit stability limit 2 / sqrt(lambda_max(M^-1 K)) at `s`, K = -df/dx by central
// differences of every force (undamped model, so the limit is exactly that).
double TrueStableStep(const FabricModel& model, const FabricState& s) {
  const testing::ForceFn fn = [&s](const FabricModel& m, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                   ForceSink* sink) {
    FabricState t = s;
    t.x_W_m = x;
    t.v_W_m_per_s = v;
    AccumulateForces(m, t, sink);
  };
  const Eigen::MatrixXd k = -testing::FiniteDifferenceJacobian(model, fn, s.x_W_m, s.v_W_m_per_s, false, 1e-7);
  Eigen::VectorXd m_inv_sqrt(3 * model.num_particles);
  for (int p = 0; p < model.num_particles; ++p) {
    m_inv_sqrt.segment<3>(3 * p).setConstant(1.0 / std::sqrt(model.mass_kg[p]));
  }
  const Eigen::MatrixXd a = m_inv_sqrt.asDiagonal() * (0.5 * (k + k.transpose())) * m_inv_sqrt.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(a, Eigen::EigenvaluesOnly);
  return 2.0 / std::sqrt(es.eigenvalues().maxCoeff());
}

// Tension raises the stiffness above what the configuration estimate assumes (the curves'
// steepest slopes on rest geometry): the shear stiffness grows with |U| |V|, and the tension adds
// stiffness across the fibre. On a soft knit stretched 3.5x the configuration estimate exceeds the
// true limit; the estimate at the state stays below it, and the stepper takes more substeps.
TEST(SymplecticEulerTest, StabilityEstimateAccountsForTension) {
  ModelOptions undamped;
  undamped.damping = {0.0, 0.0, 0.0};
  undamped.drag.linear_N_s_per_m3 = 0.0;
  undamped.drag.quadratic_coefficient = 0.0;
  const FabricModel model = BuildFabricModel(
      MaterialFromKes(testing::LoadDatabaseFabric("wang2011_navy_sparkle_sweat")), {0.2, 0.2, 7, 7}, undamped);
  Eigen::VectorXd row;
  for (const double stretch : {1.0, 3.5}) {
    FabricState s = MakeRestState(model);
    for (int p = 0; p < model.num_particles; ++p) {
      s.x(p).head<2>() *= stretch;
      s.x(p).z() += 1e-3 * std::sin(3.0 * p);  // off the plane: no exactly degenerate geometry
    }
    const double truth = TrueStableStep(model, s);
    const double at_state = EstimateExplicitStableStep(model, s, &row);
    std::printf(
        "[table] stretch %.1f: true limit %.3g s, configuration estimate %.3g s, "
        "estimate at the state %.3g s\n",
        stretch, truth, EstimateExplicitStableStep(model), at_state);
    EXPECT_LE(at_state, truth) << "stretch " << stretch;
    EXPECT_LE(std::min(at_state, EstimateExplicitStableStep(model)), truth);
    if (stretch > 1.0) {
      // What the configuration estimate alone got wrong.
      EXPECT_GT(EstimateExplicitStableStep(model), truth);
    }
  }

  // The stepper: the fabric held stretched 3.5x in a frame (border fixed) takes more substeps
  // than configured and stays calm.
  FabricState s = MakeRestState(model);
  for (int p = 0; p < model.num_particles; ++p) {
    s.x(p).head<2>() *= 3.5;
    s.x(p).z() += 1e-4 * std::sin(3.0 * p);
    if (model.mesh.IsBorder(p)) s.Fix(p);
  }
  StepOptions opt;
  opt.method = Integrator::kSymplecticEuler;
  opt.dt_s = 0.005;
  FabricStepper stepper(model, opt);
  const int configured = stepper.substeps();
  for (int i = 0; i < 100; ++i) stepper.Step(&s);
  EXPECT_GT(stepper.substeps(), configured);
  EXPECT_EQ(s.diagnostics.nan_events, 0);
  EXPECT_EQ(s.diagnostics.speed_capped, 0);
  EXPECT_EQ(s.diagnostics.substeps_limited, 0);
  EXPECT_LT(MaxSpeed(s), 1.0);
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
