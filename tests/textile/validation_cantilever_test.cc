// Validation 2: Peirce cantilever. A strip pushed over a platform edge bends under its weight;
// the overhang l at which the chord from the edge to the tip reaches 41.5 deg is l = 2 c,
// c = (B / w)^(1/3), exact to 0.02 % against the heavy elastica (docs/physics-reference.md section 4.2).

#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Static chord angle [deg] of a cantilever with overhang `l` resolved by `n` cells.
double ChordAngleDeg(const FabricMaterial& material, double l, int n) {
  const double width = 0.02;
  const FabricModel model = BuildFabricModel(material, {l * (n + 1) / n, width, n + 2, 3});
  FabricState s = MakeRestState(model);  // warp along +x, gravity -z
  for (int j = 0; j < 3; ++j) {
    s.Fix(model.mesh.Index(0, j));
    s.Fix(model.mesh.Index(1, j));
  }
  StepOptions opt;
  opt.dt_s = 0.02;
  opt.cg_tolerance = 1e-9;
  opt.cg_max_iterations = 5000;
  FabricStepper stepper(model, opt);
  testing::RunToRest(&stepper, &s, 20000, 1e-7);
  double angle = 0.0;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d d = s.x(model.mesh.Index(n + 1, j)) - s.x(model.mesh.Index(1, j));
    angle += std::atan2(-d.z(), d.x()) * 180.0 / kPi / 3.0;
  }
  return angle;
}

// Overhang at which the chord reaches `target_deg` (secant iterations).
double OverhangAtAngle(const FabricMaterial& material, double guess, int n, double target_deg) {
  double l0 = guess, l1 = 1.05 * guess;
  double f0 = ChordAngleDeg(material, l0, n) - target_deg;
  double f1 = ChordAngleDeg(material, l1, n) - target_deg;
  for (int it = 0; it < 12 && std::abs(f1) > 1e-3; ++it) {
    const double l2 = l1 - f1 * (l1 - l0) / (f1 - f0);
    l0 = l1;
    f0 = f1;
    l1 = l2;
    f1 = ChordAngleDeg(material, l1, n) - target_deg;
  }
  return l1;
}

TEST(CantileverValidationTest, PeirceOverhangWithinFivePercentAndErrorShrinks) {
  const FabricMaterial material = MaterialFromKes(testing::LoadDatabaseFabric("wang2011_royal_target"));
  const double w = material.density_kg_per_m2 * 9.81;
  const double c = std::cbrt(material.bending_warp_Nm / w);
  const double peirce = 2.0 * c;
  std::vector<double> errors;
  for (int n : {5, 10, 20, 40}) {
    const double l = OverhangAtAngle(material, peirce, n, 41.5);
    const double err = std::abs(l - peirce) / peirce;
    std::printf("[table] Peirce cantilever n=%d cells: overhang %.3f mm, Peirce %.3f mm, error %.3f %%\n", n, 1e3 * l,
                1e3 * peirce, 100 * err);
    errors.push_back(err);
  }
  EXPECT_LE(errors.back(), 0.05);
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[2], errors[1]);
  EXPECT_LT(errors[3], errors[2]);
}

}  // namespace
}  // namespace haptex::textile
