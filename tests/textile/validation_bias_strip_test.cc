// Validation: a fabric cut at an angle to the grid (ModelOptions::material_angle_rad). A strip on
// the bias (45 deg) in uniaxial tension at small strain has the stiffness per width
// k45 = 4 / (1/k_u + 1/k_v + 1/G) (docs/derivations/bias_strip.py); at 90 deg warp and weft swap.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "libs/textile/external_force.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

double SlopeAtZero(const StrainCurve& curve) {
  double f = 0.0, slope = 0.0;
  curve.Evaluate(0.0, &f, &slope);
  return slope;
}

// Stiffness per width [N/m] of a free strip along the grid's u axis, pulled at both ends by a
// force per width `tension_N_per_m` spread over each end edge: no clamp restrains its lateral
// contraction or shear, so it is in uniaxial tension everywhere (the homogeneous state is the
// discrete equilibrium: every triangle has the same strain, interior forces cancel).
double StripStiffnessNPerM(const FabricMaterial& material, double angle_deg, double tension_N_per_m) {
  const double length_m = 0.10, width_m = 0.02;
  ModelOptions options;
  options.material_angle_rad = angle_deg * kDegToRad;
  options.gravity_m_per_s2.setZero();
  const FabricModel model = BuildFabricModel(material, {length_m, width_m, 41, 9}, options);
  FabricState s = MakeRestState(model);
  const int nu = model.mesh.particles_warp(), nv = model.mesh.particles_weft();
  std::vector<int> left, right;
  for (int j = 0; j < nv; ++j) {
    left.push_back(model.mesh.Index(0, j));
    right.push_back(model.mesh.Index(nu - 1, j));
  }
  AddEdgeLoad(model, left, Eigen::Vector3d(-tension_N_per_m * width_m, 0, 0), &s);
  AddEdgeLoad(model, right, Eigen::Vector3d(tension_N_per_m * width_m, 0, 0), &s);
  StepOptions step;
  step.dt_s = 0.02;
  step.cg_tolerance = 1e-10;
  step.cg_max_iterations = 5000;
  FabricStepper stepper(model, step);
  testing::RunToRest(&stepper, &s, 20000, 1e-10);
  // End edges' mean positions: rigid rotation of the sheared strip is second order in strain.
  double stretched_m = 0.0;
  for (int j = 0; j < nv; ++j) stretched_m += (s.x(right[j]) - s.x(left[j])).norm() / nv;
  const double strain = stretched_m / length_m - 1.0;
  return tension_N_per_m / strain;
}

// A woven with warp and weft far apart (Wang et al.'s 11 oz denim: 411 and 2028 N/m), linear
// curves: their slope at zero is the small-strain stiffness.
FabricMaterial Denim() { return MaterialFromKes(testing::LoadDatabaseFabric("wang2011_black_denim_11oz")); }

TEST(BiasStripValidationTest, FortyFiveDegreesMatchesTheSmallStrainClosedForm) {
  const FabricMaterial material = Denim();
  const double k_u = SlopeAtZero(material.tensile_warp), k_v = SlopeAtZero(material.tensile_weft);
  const double g = SlopeAtZero(material.shear);
  const double k45 = 4.0 / (1.0 / k_u + 1.0 / k_v + 1.0 / g);
  // Strain about 1e-4: the closed form is the linear theory; the simulated strip's departures
  // are quadratic in the strains (|U| - 1 and U.V against the small-strain tensor), here a yarn
  // rotation of order the strain, so a relative error of order 1e-4.
  const double tension_N_per_m = 1e-4 * k45;
  const double k = StripStiffnessNPerM(material, 45.0, tension_N_per_m);
  std::printf(
      "[table] bias strip 45 deg: k_u %.2f, k_v %.2f, G %.3f N/m; simulated %.4f N/m, k45 %.4f N/m, "
      "error %.4f %%\n",
      k_u, k_v, g, k, k45, 100.0 * (k / k45 - 1.0));
  EXPECT_NEAR(k / k45, 1.0, 1e-3);
  // -45 deg is the mirror image: the same stiffness.
  EXPECT_NEAR(StripStiffnessNPerM(material, -45.0, tension_N_per_m) / k45, 1.0, 1e-3);
}

TEST(BiasStripValidationTest, NinetyDegreesSwapsWarpAndWeft) {
  const FabricMaterial material = Denim();
  const double k_u = SlopeAtZero(material.tensile_warp), k_v = SlopeAtZero(material.tensile_weft);
  const double k0 = StripStiffnessNPerM(material, 0.0, 1e-4 * k_u);
  const double k90 = StripStiffnessNPerM(material, 90.0, 1e-4 * k_v);
  std::printf("[table] strip 0 deg: %.3f N/m (k_u %.3f); 90 deg: %.3f N/m (k_v %.3f)\n", k0, k_u, k90, k_v);
  EXPECT_NEAR(k0 / k_u, 1.0, 1e-3);
  EXPECT_NEAR(k90 / k_v, 1.0, 1e-3);

  // The whole model swaps, bending included: a hanging cloth at 90 deg moves as the same cloth
  // with the warp and weft laws exchanged at 0 deg (to round-off: cos 90 deg is 6e-17, not 0).
  FabricMaterial swapped = material;
  std::swap(swapped.tensile_warp, swapped.tensile_weft);
  std::swap(swapped.bending_warp_Nm, swapped.bending_weft_Nm);
  ModelOptions turned;
  turned.material_angle_rad = 90.0 * kDegToRad;
  const GridSpec grid{0.1, 0.1, 11, 11};
  const FabricModel model_turned = BuildFabricModel(material, grid, turned);
  const FabricModel model_swapped = BuildFabricModel(swapped, grid);
  const Placement hanging{{0, 0, 0}, {1, 0, 0}, {0, 0.6, -0.8}};
  FabricState s_turned = MakeRestState(model_turned, hanging);
  FabricState s_swapped = MakeRestState(model_swapped, hanging);
  for (int i = 0; i < 11; ++i) {
    s_turned.Fix(i);
    s_swapped.Fix(i);
  }
  StepOptions step;
  step.cg_tolerance = 1e-12;
  step.cg_max_iterations = 5000;
  FabricStepper stepper_turned(model_turned, step), stepper_swapped(model_swapped, step);
  for (int k = 0; k < 50; ++k) {
    stepper_turned.Step(&s_turned);
    stepper_swapped.Step(&s_swapped);
  }
  const double moved_m = (s_swapped.x_W_m - MakeRestState(model_swapped, hanging).x_W_m).cwiseAbs().maxCoeff();
  EXPECT_GT(moved_m, 1e-3);
  EXPECT_LT((s_turned.x_W_m - s_swapped.x_W_m).cwiseAbs().maxCoeff(), 1e-9);
}

}  // namespace
}  // namespace haptex::textile
