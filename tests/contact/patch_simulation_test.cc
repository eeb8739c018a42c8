// PatchSimulation: the tick of the haptic loop (contact springs, one fabric step, forces).

#include "libs/contact/patch_simulation.h"

#include "libs/contact/haptic_step_options.h"

#include <gtest/gtest.h>

#include "tests/contact/contact_test_util.h"
#include "tests/support/allocation_counter.h"

namespace haptex::contact {
namespace {

using V = Eigen::Vector3d;

class PatchSimulationTest : public ::testing::Test {
 protected:
  PatchSimulationTest()
      : sim_(testing::MakeFlatPatch(testing::DatabaseMaterial("wang2011_black_denim_11oz"), 0.02, 21, options_,
                                    testing::LocalStep())) {}
  FingerInput Thumb(double z) const { return {true, testing::PoseFacing(V(0, 0, z), V(0, 0, -1), V::UnitX())}; }
  FingerInput Index(double z) const { return {true, testing::PoseFacing(V(0, 0, z), V(0, 0, 1), V::UnitX())}; }
  // Warmed up through one-finger contact into a pinch (the path with the most work), ticks
  // allocate nothing.
  void ExpectWarmedUpTickDoesNotAllocate() {
    if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting off (ASan)";
    const double r = options_.thumb.radius_m + options_.fabric_half_thickness_m;
    for (int k = 0; k < 50; ++k) sim_->Tick(Thumb(r - 0.001), {});
    for (int k = 0; k < 50; ++k) sim_->Tick(Thumb(r - 0.002), Index(-(r - 0.002)));
    ASSERT_EQ(
        sim_->solver().output().state == ContactState::kVIII || sim_->solver().output().state == ContactState::kIX,
        true)
        << ToString(sim_->solver().output().state);
    haptex::testing::AllocationCounter counter;
    for (int k = 0; k < 50; ++k) {
      sim_->Tick(Thumb(r - 0.002 + 1e-5 * k), Index(-(r - 0.002) + 1e-5 * k));
    }
    for (int k = 0; k < 20; ++k) sim_->Tick(Thumb(r - 0.001), {});
    EXPECT_EQ(counter.count(), 0);
  }
  ContactOptions options_;
  std::unique_ptr<PatchSimulation> sim_;
};

TEST_F(PatchSimulationTest, NoFingersNoForce) {
  const ContactOutput& out = sim_->Tick({}, {});
  EXPECT_EQ(out.state, ContactState::kI);
  EXPECT_EQ(out.finger[kThumb].force_W_N, V::Zero());
  EXPECT_EQ(sim_->solver().particle_force_W_N().norm(), 0.0);
}

TEST_F(PatchSimulationTest, ContactForceIsActionReaction) {
  const double r = options_.thumb.radius_m + options_.fabric_half_thickness_m;
  for (int k = 0; k < 100; ++k) sim_->Tick(Thumb(r - 0.001), {});
  const ContactOutput& out = sim_->Tick(Thumb(r - 0.001), {});
  ASSERT_GT(out.finger[kThumb].contact_particles, 0);
  // The fabric pushes the finger up; the particles get the opposite, summed.
  const Eigen::VectorXd& f = sim_->solver().particle_force_W_N();
  V on_fabric = V::Zero();
  for (int p = 0; p < sim_->model().num_particles; ++p) on_fabric += f.segment<3>(3 * p);
  EXPECT_GT(out.finger[kThumb].force_W_N.z(), 0.0);
  EXPECT_TRUE((on_fabric + out.finger[kThumb].force_W_N).norm() < 1e-9 * (1 + on_fabric.norm()));
  EXPECT_NEAR(out.finger[kThumb].touch_uv_m.x(), 0.01, 0.002);  // the patch centre
  EXPECT_NEAR(out.finger[kThumb].touch_uv_m.y(), 0.01, 0.002);
}

TEST_F(PatchSimulationTest, NonFiniteFingerIsIgnoredAndCounted) {
  FingerInput bad = Thumb(0.0);
  bad.pose.p_W_m.x() = std::numeric_limits<double>::quiet_NaN();
  const ContactOutput& out = sim_->Tick(bad, {});
  EXPECT_EQ(out.finger[kThumb].force_W_N, V::Zero());
  EXPECT_EQ(sim_->solver().diagnostics().non_finite_inputs, 1);
  EXPECT_TRUE(sim_->state().x_W_m.allFinite());
}

TEST_F(PatchSimulationTest, WarmedUpTickDoesNotAllocate) { ExpectWarmedUpTickDoesNotAllocate(); }

// The same with local_contact's haptic step (Gauss-Seidel PCG).
TEST_F(PatchSimulationTest, WarmedUpHapticTickDoesNotAllocate) {
  sim_ = testing::MakeFlatPatch(testing::DatabaseMaterial("wang2011_black_denim_11oz"), 0.02, 21, options_,
                                HapticPatchStepOptions(0.001));
  ExpectWarmedUpTickDoesNotAllocate();
}

}  // namespace
}  // namespace haptex::contact
