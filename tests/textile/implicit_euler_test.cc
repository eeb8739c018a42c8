#include "libs/textile/implicit_euler.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "libs/textile/anchor_spring_force.h"
#include "libs/textile/external_force.h"
#include "libs/textile/fabric_forces.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/validation.h"
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

// Implicit Euler's unit: these tests pin it (BDF2 runs the same solve on other inputs:
// fabric_stepper_test.cc).
TEST_F(ImplicitEulerTest, FreeFallIsExactInVelocity) {
  ModelOptions o;
  o.drag.linear_N_s_per_m3 = 0.0;
  o.drag.quadratic_coefficient = 0.0;
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 5, 5}, o);
  FabricState s = MakeRestState(model);
  StepOptions opt;
  opt.method = Integrator::kImplicitEuler;
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
  opt.method = Integrator::kImplicitEuler;
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
  opt.method = Integrator::kImplicitEuler;
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
  opt.method = Integrator::kImplicitEuler;
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
  for (const Integrator method : {Integrator::kImplicitEuler, Integrator::kBdf2}) {
    FabricState s = Hanging(model);
    SetPointLoad(model.mesh.Index(20, 10), Eigen::Vector3d(0, 1.0, 0), &s);
    StepOptions opt;
    opt.method = method;
    if (method == Integrator::kBdf2) opt.newton_max_iterations = 4;
    FabricStepper stepper(model, opt);
    for (int i = 0; i < 3; ++i) stepper.Step(&s);
    haptex::testing::AllocationCounter counter;
    for (int i = 0; i < 5; ++i) stepper.Step(&s);
    stepper.RestartHistory();
    stepper.Step(&s);
    EXPECT_EQ(counter.count(), 0) << IntegratorName(method);
  }
}

// Implicit Euler's equations at a step's end, evaluated from the forces alone (not from the
// solver's own bookkeeping): |h f(x1, v1) - M (v1 - v0)| over the free particles, and the
// largest |x1 - x0 - h v1|.
struct StepEquations {
  double residual = 0.0;
  double position_mismatch_m = 0.0;
};
StepEquations CheckStepEquations(const FabricModel& model, const FabricState& before, const FabricState& after,
                                 double h) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * model.num_particles);
  ForceSink sink;
  sink.force_N = &f;
  AccumulateForces(model, after, &sink);
  AddAnchorSpringForces(model, after, &sink);
  StepEquations e;
  double sum2 = 0.0;
  for (int p = 0; p < model.num_particles; ++p) {
    if (after.mode[static_cast<std::size_t>(p)] != ParticleMode::kFree) continue;
    sum2 += (h * f.segment<3>(3 * p) - model.mass_kg[p] * (after.v(p) - before.v(p))).squaredNorm();
    e.position_mismatch_m = std::max(e.position_mismatch_m, (after.x(p) - before.x(p) - h * after.v(p)).norm());
  }
  e.residual = std::sqrt(sum2);
  return e;
}

// |h M g| over the free particles: the force level of the residual tolerance at rest.
double WeightImpulse(const FabricModel& model, const FabricState& s, double h) {
  double sum2 = 0.0;
  for (int p = 0; p < model.num_particles; ++p) {
    if (s.mode[static_cast<std::size_t>(p)] == ParticleMode::kFree) sum2 += model.mass_kg[p] * model.mass_kg[p];
  }
  return h * 9.81 * std::sqrt(sum2);
}

class NewtonTest : public ImplicitEulerTest {
 protected:
  // A hanging cloth shaken (random displacements of 1 mm and velocities of 0.2 m/s): one
  // linearised step of 20 ms is far from the nonlinear solution.
  void SetUp() override {
    model_ = std::make_unique<FabricModel>(MakeModel(11));
    start_ = Hanging(*model_);
    validation::Perturb(&start_, 0.001, 0.2, 7);
  }
  std::unique_ptr<FabricModel> model_;
  FabricState start_;
};

// Newton's iterations solve implicit Euler's equations themselves, where Baraff-Witkin's single
// linearised step leaves a large residual; the loose CG tolerance is tightened to what the
// Newton tolerance needs.
TEST_F(NewtonTest, IterationsSolveTheNonlinearStep) {
  StepOptions single;
  single.dt_s = 0.02;
  single.newton_max_iterations = 1;
  StepOptions newton = single;
  newton.newton_max_iterations = 64;
  newton.newton_tolerance = 1e-5;
  newton.cg_tolerance = 0.5;  // the loosest allowed: the Newton target sets the precision
  newton.cg_max_iterations = 1000;
  FabricState a = start_, b = start_;
  FabricWorkspace wa(*model_, single.preconditioner), wb(*model_, newton.preconditioner);
  const ImplicitStepReport ra = ImplicitEulerStep(*model_, single, &a, &wa);
  const ImplicitStepReport rb = ImplicitEulerStep(*model_, newton, &b, &wb);
  const StepEquations ea = CheckStepEquations(*model_, start_, a, 0.02);
  const StepEquations eb = CheckStepEquations(*model_, start_, b, 0.02);
  std::cout << "[measured] residual impulse: one step " << ea.residual << " N s, Newton " << eb.residual
            << " N s after " << rb.newton_iterations << " iterations\n";
  EXPECT_EQ(ra.newton_iterations, 1);
  EXPECT_GT(rb.newton_iterations, 2);
  EXPECT_TRUE(rb.newton_converged);
  EXPECT_LE(rb.newton_relative_residual, 1e-5);
  EXPECT_GT(ea.residual, 1e-3 * WeightImpulse(*model_, start_, 0.02)) << "not nonlinear enough to tell";
  EXPECT_LT(eb.residual, 1e-2 * ea.residual);
  EXPECT_LT(eb.position_mismatch_m, 1e-12);
  EXPECT_NEAR(b.time_s, start_.time_s + 0.02, 1e-15);
}

// Too few iterations for the tolerance: the step is still taken, and says so.
TEST_F(NewtonTest, TooFewIterationsAreReported) {
  StepOptions o;
  o.method = Integrator::kImplicitEuler;
  o.dt_s = 0.02;
  o.newton_max_iterations = 2;
  o.newton_tolerance = 1e-12;
  FabricState s = start_;
  FabricWorkspace ws(*model_, o.preconditioner);
  const ImplicitStepReport r = ImplicitEulerStep(*model_, o, &s, &ws);
  EXPECT_EQ(r.newton_iterations, 2);
  EXPECT_FALSE(r.newton_converged);
  EXPECT_GT(r.newton_relative_residual, 1e-12);
  EXPECT_TRUE(r.cg.finite);
}

// The chord method (the first matrix kept) overshoots where elements go from compression (2 % of
// the tangent) to tension within the step; it diverges and says so, never claims convergence.
TEST_F(NewtonTest, TheChordMethodSaysWhenItDiverges) {
  StepOptions o;
  o.method = Integrator::kImplicitEuler;
  o.dt_s = 0.02;
  o.newton_max_iterations = 8;
  o.newton_update_jacobian = false;
  FabricState s = start_;
  FabricWorkspace ws(*model_, o.preconditioner);
  const ImplicitStepReport r = ImplicitEulerStep(*model_, o, &s, &ws);
  EXPECT_FALSE(r.newton_converged);
  FabricStepper stepper(*model_, o);
  FabricState t = start_;
  stepper.Step(&t);
  EXPECT_TRUE(t.x_W_m.allFinite()) << "the stepper rolls a diverged step back";
  EXPECT_EQ(t.diagnostics.newton_not_converged + t.diagnostics.nan_events > 0, true);
}

// A cloth at rest without loads needs no correction: the first check meets the tolerance.
TEST_F(NewtonTest, AClothAtRestConvergesAtTheFirstCheck) {
  StepOptions o;
  o.method = Integrator::kImplicitEuler;
  o.newton_max_iterations = 10;
  ModelOptions weightless;
  weightless.gravity_m_per_s2.setZero();
  const FabricModel model =
      BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.2, 0.2, 11, 11}, weightless);
  FabricState s = MakeRestState(model);
  for (const bool reassemble : {true, false}) {
    o.newton_update_jacobian = reassemble;
    FabricWorkspace ws(model, o.preconditioner);
    const ImplicitStepReport r = ImplicitEulerStep(model, o, &s, &ws);
    EXPECT_EQ(r.newton_iterations, 1);
    EXPECT_TRUE(r.newton_converged);
  }
}

TEST_F(ImplicitEulerTest, NewtonAndSplittingDoNotAllocate) {
  if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting off";
  const FabricModel model = MakeModel(21);
  for (const Integrator method : {Integrator::kImplicitEuler, Integrator::kBdf2}) {
    FabricState s = Hanging(model);
    SetPointLoad(model.mesh.Index(20, 10), Eigen::Vector3d(0, 5.0, 0), &s);
    StepOptions opt;
    opt.method = method;
    opt.dt_s = 0.05;
    opt.newton_max_iterations = 3;
    opt.newton_tolerance = 1e-9;  // never met: every step splits to the bottom
    opt.max_step_halvings = 2;
    opt.max_strain_rise_per_step = 1e-6;
    FabricStepper stepper(model, opt);
    for (int i = 0; i < 3; ++i) stepper.Step(&s);
    haptex::testing::AllocationCounter counter;
    for (int i = 0; i < 3; ++i) stepper.Step(&s);
    EXPECT_EQ(counter.count(), 0) << IntegratorName(method);
    EXPECT_GT(s.diagnostics.step_halvings, 0);
  }
}

}  // namespace
}  // namespace haptex::textile
