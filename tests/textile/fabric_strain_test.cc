#include "libs/textile/fabric_strain.h"

#include <gtest/gtest.h>

#include "libs/textile/kes_material.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

TEST(FabricStrainTest, UniformStretchIsTheLargerOfWarpAndWeft) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.2, 5, 7});
  FabricState s = MakeRestState(model);
  EXPECT_NEAR(LargestTensileStrain(model, s.x_W_m), 0.0, 1e-14);
  for (int p = 0; p < model.num_particles; ++p) {
    s.x_W_m[3 * p] *= 1.03;      // along u (warp)
    s.x_W_m[3 * p + 1] *= 0.99;  // along v (weft): compressed
  }
  EXPECT_NEAR(LargestTensileStrain(model, s.x_W_m), 0.03, 1e-12);
  for (int p = 0; p < model.num_particles; ++p) s.x_W_m[3 * p] /= 1.03 / 0.98;
  EXPECT_NEAR(LargestTensileStrain(model, s.x_W_m), -0.01, 1e-12) << "all compressed: the least compressed";
}

TEST(FabricStrainTest, OneStretchedElementDecides) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 5, 5});
  FabricState s = MakeRestState(model);
  s.x(model.mesh.Index(4, 4)) += Eigen::Vector3d(0.01, 0.0, 0.0);  // a corner pulled outwards
  EXPECT_GT(LargestTensileStrain(model, s.x_W_m), 0.2);
}

}  // namespace
}  // namespace haptex::textile
