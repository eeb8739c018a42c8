// Validation 2: Peirce cantilever. A strip pushed over a platform edge bends under its weight;
// the overhang l at which the chord from the edge to the tip reaches 41.5 deg is l = 2 c,
// c = (B / w)^(1/3), exact to 0.02 % against the heavy elastica (docs/physics-reference.md section 4.2).

#include <algorithm>
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

// The static cantilever: its chord angle, and how much its bent overhang shortened.
struct Bent {
  double chord_deg = 0.0;
  /// Largest warp compression of a triangle (|U| - 1 < 0), at the root where the curvature is
  /// largest [-].
  double root_strain = 0.0;
  /// Relative change of the overhang's length along its middle line (arc length of the particle
  /// polyline from the platform edge to the tip against l) [-].
  double overhang_strain = 0.0;
};

// Static cantilever with overhang `l` resolved by `n` cells.
Bent SolveCantilever(const FabricMaterial& material, double l, int n) {
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
  Bent bent;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d d = s.x(model.mesh.Index(n + 1, j)) - s.x(model.mesh.Index(1, j));
    bent.chord_deg += std::atan2(-d.z(), d.x()) * 180.0 / kPi / 3.0;
  }
  for (const TriangleElement& e : model.triangles) {
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) u += e.a[k] * s.x(e.p[k]);
    bent.root_strain = std::min(bent.root_strain, u.norm() - 1.0);
  }
  double arc_m = 0.0;
  for (int i = 1; i <= n; ++i) arc_m += (s.x(model.mesh.Index(i + 1, 1)) - s.x(model.mesh.Index(i, 1))).norm();
  bent.overhang_strain = arc_m / l - 1.0;
  return bent;
}

double ChordAngleDeg(const FabricMaterial& material, double l, int n) {
  return SolveCantilever(material, l, n).chord_deg;
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

namespace haptex::textile {
namespace {

// A fabric bends at constant length: its mid-surface is the neutral plane. The grid-line bending
// elements pull a bent segment shorter with about B kappa^2 per width, so the overhang shortens
// by that over the compression slope. Compression at 2 % of tension (the former default) against
// the tension's own slope (KesConversionOptions's default now).
TEST(CantileverValidationTest, BentStripKeepsItsLength) {
  const kes::Fabric royal = testing::LoadDatabaseFabric("wang2011_royal_target");
  // The soft knit's tensile laws under the royal target's bending and mass: the same bend, a
  // fabric 160 times softer in the plane.
  kes::Fabric soft = royal;
  const kes::Fabric knit = testing::LoadDatabaseFabric("wang2011_navy_sparkle_sweat");
  soft.warp_tensile = knit.warp_tensile;
  soft.weft_tensile = knit.weft_tensile;
  KesConversionOptions soft_compression;
  soft_compression.compression_fraction = 0.02;
  const int n = 40;
  for (const auto& [name, fabric] : {std::pair<const char*, kes::Fabric>{"royal target", royal},
                                     std::pair<const char*, kes::Fabric>{"royal target, soft knit's curves", soft}}) {
    const FabricMaterial material = MaterialFromKes(fabric);
    const double l = 2.0 * std::cbrt(material.bending_warp_Nm / (material.density_kg_per_m2 * 9.81));
    const Bent before = SolveCantilever(MaterialFromKes(fabric, soft_compression), l, n);
    const Bent after = SolveCantilever(material, l, n);
    std::printf(
        "[table] bent strip (%s, overhang 2c = %.3f mm, n=40): compression 2 %% of tension: root %.4f %%, "
        "overhang %.4f %%, chord %.3f deg; compression = tension slope: root %.4f %%, overhang %.4f %%, "
        "chord %.3f deg\n",
        name, 1e3 * l, 100 * before.root_strain, 100 * before.overhang_strain, before.chord_deg,
        100 * after.root_strain, 100 * after.overhang_strain, after.chord_deg);
    // Measured: the root's compression 40x (royal target) and 8x (soft knit: at 25 N/m the
    // pull B kappa^2 still compresses the root 0.3 %) smaller, the overhang's length change 0.0002 %
    // and 0.04 % (from -0.012 % and -0.36 %).
    EXPECT_GT(before.root_strain / after.root_strain, 5.0);  // both negative
    EXPECT_GT(after.root_strain, -5e-3);
    EXPECT_LT(std::abs(after.overhang_strain), 1e-3);
    EXPECT_LT(std::abs(after.overhang_strain), 0.2 * std::abs(before.overhang_strain));
  }
}

}  // namespace
}  // namespace haptex::textile
