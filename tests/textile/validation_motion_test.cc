// Accuracy in motion (libs/textile/motion_accuracy.h) on a small mesh: the converged step (implicit
// Euler's and BDF2's) approaches the reference as the step shrinks, BDF2 comes closer at the same
// step, and neither creates energy after the push ends; the counts the solver reports are those
// of the run. The full table is the benchmark's
// (bench/textile/dynamic_accuracy, docs/fabric-model.md "Accuracy in motion").
#include "libs/textile/motion_accuracy.h"

#include <iostream>

#include <gtest/gtest.h>

#include "libs/textile/kes_material.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile::validation {
namespace {

class MotionAccuracyTest : public ::testing::TestWithParam<MotionKind> {
 protected:
  MotionAccuracyTest()
      : model_(BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.2, 0.2, 11, 11})),
        motion_(MakeMotion(GetParam(), model_, SettledHanging(model_))),
        reference_(RunMotion(motion_, model_, ConvergedOptions(5e-4))) {}

  MotionErrors Errors(double dt_s, Integrator method = Integrator::kBdf2) {
    StepOptions o = ConvergedOptions(dt_s);
    o.method = method;
    o.newton_tolerance = 1e-6;
    o.cg_tolerance = 1e-6;
    const MotionTrace run = RunMotion(motion_, model_, o);
    EXPECT_EQ(run.nan_events, 0);
    const MotionErrors e = CompareMotion(motion_, run, reference_);
    std::cout << "[measured] " << MotionKindName(GetParam()) << " " << IntegratorName(method) << " dt " << dt_s * 1e3
              << " ms: peak strain " << e.peak_strain_pct << " %, strain in time " << e.strain_in_time_pct
              << " %, positions " << e.position_rms_mm << " mm RMS, energy " << e.energy_pct << " %, growth "
              << e.energy_growth_pct << " %, Newton " << run.newton_iterations_per_step << " per step, not converged "
              << run.newton_not_converged << "\n";
    return e;
  }

  FabricModel model_;
  Motion motion_;
  MotionTrace reference_;
};

// BDF2 (the reference's integrator) converges to it: a fifth of the step, positions, strain and
// energy closer. Implicit Euler converges only at first order towards it (its damping): its
// positions come closer.
TEST_P(MotionAccuracyTest, ConvergedStepsApproachTheReferenceAsTheStepShrinks) {
  const MotionErrors coarse = Errors(0.01);
  const MotionErrors fine = Errors(0.002);
  EXPECT_LT(fine.position_rms_mm, 0.5 * coarse.position_rms_mm);
  EXPECT_LT(fine.strain_in_time_pct, coarse.strain_in_time_pct);
  EXPECT_LT(fine.energy_pct, coarse.energy_pct);
  EXPECT_LT(Errors(0.002, Integrator::kImplicitEuler).position_rms_mm,
            Errors(0.01, Integrator::kImplicitEuler).position_rms_mm);
}

// Second order against first: at the same step BDF2's positions are closer, by half or more
// where the cloth moves freely (the swing, the whole-cloth push); the slow pinch is quasi-static
// and both stay within a micrometre.
TEST_P(MotionAccuracyTest, Bdf2IsCloserThanImplicitEulerAtTheSameStep) {
  const MotionErrors euler = Errors(0.005, Integrator::kImplicitEuler);
  const MotionErrors bdf2 = Errors(0.005, Integrator::kBdf2);
  if (GetParam() == MotionKind::kPinch) {
    EXPECT_LT(euler.position_rms_mm, 1e-3);
    EXPECT_LT(bdf2.position_rms_mm, 1e-3);
    return;
  }
  const bool free_motion = GetParam() == MotionKind::kSwing || GetParam() == MotionKind::kPushWhole;
  EXPECT_LT(bdf2.position_rms_mm, (free_motion ? 0.5 : 1.0) * euler.position_rms_mm);
  EXPECT_LT(bdf2.energy_pct, euler.energy_pct);
}

// The whole-cloth push loads every free particle by its mass: together, twice the cloth's weight.
TEST(PushWholeTest, LoadsEveryFreeParticleByItsMassWithTwiceTheWeight) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.2, 0.2, 11, 11});
  const FabricState settled = SettledHanging(model);
  const Motion m = MakeMotion(MotionKind::kPushWhole, model, settled);
  int free = 0;
  double loaded_kg = 0.0, share = 0.0;
  for (int p = 0; p < model.num_particles; ++p) free += settled.mode[p] == ParticleMode::kFree;
  ASSERT_EQ(static_cast<int>(m.gripped.size()), free);
  ASSERT_EQ(m.push_share.size(), m.gripped.size());
  for (std::size_t i = 0; i < m.gripped.size(); ++i) {
    loaded_kg += model.mass_kg[m.gripped[i]];
    share += m.push_share[i];
    EXPECT_GT(m.push_share[i], 0.0);
  }
  for (std::size_t i = 0; i < m.gripped.size(); ++i)
    EXPECT_NEAR(m.push_share[i], model.mass_kg[m.gripped[i]] / loaded_kg, 1e-15);
  EXPECT_NEAR(share, 1.0, 1e-12);
  EXPECT_NEAR(m.push_W_N.norm(), 2.0 * model.mass_kg.sum() * model.options.gravity_m_per_s2.norm(), 1e-12);
  EXPECT_NEAR(m.push_W_N.normalized().dot(Eigen::Vector3d::UnitY()), 1.0, 1e-12) << "normal to the hanging cloth";
}

// Both integrators dissipate: once nothing does work on the cloth (after the push; the swing from
// the start), its energy only falls. The reference's own run is checked, and coarse ones.
using ReleasedMotionTest = MotionAccuracyTest;
TEST_P(ReleasedMotionTest, NoEnergyIsCreatedAfterTheRelease) {
  EXPECT_LT(CompareMotion(motion_, reference_, reference_).energy_growth_pct, 0.01);
  EXPECT_LT(Errors(0.01, Integrator::kImplicitEuler).energy_growth_pct, 0.01);
  EXPECT_LT(Errors(0.01, Integrator::kBdf2).energy_growth_pct, 0.01);
}

std::string NameOf(const ::testing::TestParamInfo<MotionKind>& param) { return MotionKindName(param.param); }
INSTANTIATE_TEST_SUITE_P(Motions, MotionAccuracyTest,
                         ::testing::Values(MotionKind::kSwing, MotionKind::kPush, MotionKind::kPushWhole,
                                           MotionKind::kPinch),
                         NameOf);
// the pinch's grip does work throughout: no release
INSTANTIATE_TEST_SUITE_P(Motions, ReleasedMotionTest,
                         ::testing::Values(MotionKind::kSwing, MotionKind::kPush, MotionKind::kPushWhole), NameOf);

TEST(MotionKindTest, NamesRoundTripAndUnknownNamesAreRefused) {
  for (const MotionKind kind : {MotionKind::kSwing, MotionKind::kPush, MotionKind::kPushWhole, MotionKind::kPinch}) {
    EXPECT_EQ(MotionKindNamed(MotionKindName(kind)), kind);
  }
  EXPECT_THROW(MotionKindNamed("wave"), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::textile::validation
