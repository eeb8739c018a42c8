#include "libs/textile/external_force.h"

#include <gtest/gtest.h>

#include "libs/textile/kes_material.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

TEST(ExternalForceTest, EdgeLoadSumsToTotalAndIsUniformPerLength) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.38, 0.2, 17, 15});
  FabricState s = MakeRestState(model);
  const auto row = testing::WarpRow(model, 16);
  AddEdgeLoad(model, row, Eigen::Vector3d(0, 0, -1.4), &s);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int p : row) total += s.external_force_W_N.segment<3>(3 * p);
  EXPECT_NEAR((total - Eigen::Vector3d(0, 0, -1.4)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(s.external_force_W_N[3 * row[0] + 2] * 2, s.external_force_W_N[3 * row[5] + 2], 1e-12);
}

TEST(ExternalForceTest, GravityAndPointLoad) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 3, 3});
  FabricState s = MakeRestState(model);
  SetPointLoad(4, Eigen::Vector3d(1, 0, 0), &s);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * model.num_particles);
  ForceSink sink;
  sink.force_N = &f;
  AddExternalForces(model, s, &sink);
  EXPECT_NEAR(f[3 * 4], 1.0, 1e-15);
  double fz = 0.0;
  for (int p = 0; p < model.num_particles; ++p) fz += f[3 * p + 2];
  EXPECT_NEAR(fz, -9.81 * 0.01 * 0.324, 1e-12);
}

TEST(ExternalForceTest, RejectsBadChains) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 3, 3});
  FabricState s = MakeRestState(model);
  EXPECT_THROW(AddEdgeLoad(model, {}, Eigen::Vector3d::Zero(), &s), std::invalid_argument);
  EXPECT_THROW(AddEdgeLoad(model, {0, 99}, Eigen::Vector3d::Zero(), &s), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::textile
