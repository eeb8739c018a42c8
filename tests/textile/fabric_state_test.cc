#include "libs/textile/fabric_state.h"

#include <gtest/gtest.h>

#include "libs/textile/kes_material.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

class FabricStateTest : public ::testing::Test {
 protected:
  FabricModel model_ = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.2, 0.1, 5, 3});
};

TEST_F(FabricStateTest, RestStateFollowsPlacement) {
  Placement pl;
  pl.origin_W = Eigen::Vector3d(1, 2, 3);
  pl.axis_u_W = Eigen::Vector3d(0, 0, -1);
  pl.axis_v_W = Eigen::Vector3d(1, 0, 0);
  const FabricState dut = MakeRestState(model_, pl);
  EXPECT_EQ(dut.num_particles(), 15);
  const int corner = model_.mesh.Index(4, 2);
  EXPECT_NEAR((dut.x(corner) - Eigen::Vector3d(1.1, 2, 2.8)).norm(), 0.0, 1e-12);
  EXPECT_EQ(dut.v_W_m_per_s.norm(), 0.0);
  EXPECT_EQ(KineticEnergy(model_, dut), 0.0);
}

TEST_F(FabricStateTest, ConstraintsAndEnergy) {
  FabricState dut = MakeRestState(model_);
  dut.Prescribe(3, Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(dut.mode[3], ParticleMode::kPrescribed);
  EXPECT_EQ(dut.v(3), Eigen::Vector3d(0, 0, 2));
  EXPECT_DOUBLE_EQ(MaxSpeed(dut), 2.0);
  EXPECT_NEAR(KineticEnergy(model_, dut), 0.5 * model_.mass_kg[3] * 4.0, 1e-15);
  dut.Fix(3);
  EXPECT_EQ(dut.v(3).norm(), 0.0);
  dut.Free(3);
  EXPECT_EQ(dut.mode[3], ParticleMode::kFree);
}

TEST_F(FabricStateTest, RejectsNonOrthonormalPlacement) {
  Placement pl;
  pl.axis_v_W = Eigen::Vector3d(1, 1, 0);
  EXPECT_THROW(MakeRestState(model_, pl), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::textile
