#include "libs/textile/fabric_model.h"

#include <cmath>

#include <gtest/gtest.h>

#include "libs/textile/bending_force.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

class FabricModelTest : public ::testing::Test {
 protected:
  FabricMaterial material_ = MaterialFromKes(testing::CompositeDenim());
};

TEST_F(FabricModelTest, LumpedMassesSumToFabricMass) {
  const FabricModel dut = BuildFabricModel(material_, {0.38, 0.2, 17, 15});
  EXPECT_NEAR(dut.mass_kg.sum(), 0.38 * 0.2 * 0.324, 1e-12);
  EXPECT_NEAR(dut.area_m2.sum(), 0.38 * 0.2, 1e-12);
}

TEST_F(FabricModelTest, TriangleWeightsGiveUnitWarpAndWeftAtRest) {
  const FabricModel dut = BuildFabricModel(material_, {0.1, 0.05, 6, 4});
  const FabricState s = MakeRestState(dut);
  for (const auto& e : dut.triangles) {
    Eigen::Vector3d u = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) {
      u += e.a[k] * s.x(e.p[k]);
      v += e.b[k] * s.x(e.p[k]);
    }
    EXPECT_NEAR((u - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-12);
    EXPECT_NEAR((v - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(e.a[0] + e.a[1] + e.a[2], 0.0, 1e-9);
    EXPECT_NEAR(e.b[0] + e.b[1] + e.b[2], 0.0, 1e-9);
  }
}

// Bending energy on a cylinder of curvature kappa along warp equals B kappa^2 / 2 per area.
TEST_F(FabricModelTest, BendingEnergyMatchesRigidityOnACylinder) {
  const double kappa = 5.0;  // 1/m
  for (int n : {11, 21, 41}) {
    const FabricModel dut = BuildFabricModel(material_, {0.2, 0.1, n, 5});
    FabricState s = MakeRestState(dut);
    for (int p = 0; p < dut.num_particles; ++p) {
      const Eigen::Vector2d uv = dut.mesh.rest_uv_m(p);
      const double a = uv.x() * kappa;
      s.x(p) = Eigen::Vector3d(std::sin(a) / kappa, uv.y(), (1 - std::cos(a)) / kappa);
    }
    double energy = 0.0;
    for (const auto& e : dut.bends) {
      Eigen::Vector3d r = Eigen::Vector3d::Zero();
      for (std::size_t k = 0; k < 3; ++k) r += e.alpha[k] * s.x(e.p[k]);
      energy += 0.5 * e.lambda_N_per_m * r.squaredNorm();
    }
    // Triplets cover the interior of each warp line: length 0.2 - du.
    const double du = 0.2 / (n - 1);
    const double expected = 0.5 * material_.bending_warp_Nm * kappa * kappa * 0.1 * (0.2 - du);
    EXPECT_NEAR(energy / expected, 1.0, 2e-3) << "n=" << n;
  }
}

// The material angle turns the yarn vectors on the grid: at rest U is the warp direction
// (cos, sin) and V the weft (-sin, cos) in (u, v); angle 0 keeps the grid's weights exactly.
TEST_F(FabricModelTest, MaterialAngleTurnsTheYarnVectors) {
  const GridSpec grid{0.1, 0.05, 6, 4};
  const FabricModel grid_axes = BuildFabricModel(material_, grid);
  ModelOptions zero;
  zero.material_angle_rad = 0.0;
  const FabricModel explicit_zero = BuildFabricModel(material_, grid, zero);
  for (std::size_t t = 0; t < grid_axes.triangles.size(); ++t) {
    EXPECT_EQ(grid_axes.triangles[t].a, explicit_zero.triangles[t].a);
    EXPECT_EQ(grid_axes.triangles[t].b, explicit_zero.triangles[t].b);
  }
  const double angle = 0.4;
  ModelOptions options;
  options.material_angle_rad = angle;
  const FabricModel dut = BuildFabricModel(material_, grid, options);
  const FabricState s = MakeRestState(dut);
  for (const auto& e : dut.triangles) {
    Eigen::Vector3d u = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) {
      u += e.a[k] * s.x(e.p[k]);
      v += e.b[k] * s.x(e.p[k]);
    }
    EXPECT_NEAR((u - Eigen::Vector3d(std::cos(angle), std::sin(angle), 0)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((v - Eigen::Vector3d(-std::sin(angle), std::cos(angle), 0)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(e.a[0] + e.a[1] + e.a[2], 0.0, 1e-9);
    EXPECT_NEAR(e.b[0] + e.b[1] + e.b[2], 0.0, 1e-9);
  }
  // Bending: a u line is at -angle from the warp, a v line at 90 deg - angle.
  const double c2 = std::cos(angle) * std::cos(angle), s2 = std::sin(angle) * std::sin(angle);
  const double b_u = material_.bending_warp_Nm * c2 + material_.bending_weft_Nm * s2;
  const double b_v = material_.bending_warp_Nm * s2 + material_.bending_weft_Nm * c2;
  for (std::size_t k = 0; k < dut.bends.size(); ++k) {
    const bool along_u = dut.bends[k].p[1] - dut.bends[k].p[0] == 1;
    const double ratio = dut.bends[k].lambda_N_per_m / grid_axes.bends[k].lambda_N_per_m;
    EXPECT_NEAR(ratio, along_u ? b_u / material_.bending_warp_Nm : b_v / material_.bending_weft_Nm, 1e-12) << k;
  }
}

TEST_F(FabricModelTest, RejectsBadOptions) {
  ModelOptions o;
  o.damping.stretch_s = -1.0;
  EXPECT_THROW(BuildFabricModel(material_, {0.1, 0.1, 3, 3}, o), std::invalid_argument);
  o = {};
  o.gravity_m_per_s2.x() = std::nan("");
  EXPECT_THROW(BuildFabricModel(material_, {0.1, 0.1, 3, 3}, o), std::invalid_argument);
  o = {};
  o.material_angle_rad = std::nan("");
  EXPECT_THROW(BuildFabricModel(material_, {0.1, 0.1, 3, 3}, o), std::invalid_argument);
  FabricMaterial m = material_;
  m.density_kg_per_m2 = 0.0;
  EXPECT_THROW(BuildFabricModel(m, {0.1, 0.1, 3, 3}), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::textile
