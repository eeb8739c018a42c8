// Validation 1 (Boettcher et al. 2008, section 6): a 20 x 38 cm strip of 448 triangles hangs from
// its fixed top edge under gravity; a force of 0.4 .. 2.4 N pulls its bottom edge down. The static
// elongation must match the exact integral of the same tensile curve under the same load plus
// self-weight within 1 % of the elongation, at every force.

#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "libs/textile/external_force.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

struct Case {
  const char* label;
  bool composite_denim;  // else: database fabric `name`
  const char* name;
};

class TensileValidationTest : public ::testing::TestWithParam<Case> {};

TEST_P(TensileValidationTest, ElongationMatchesAnalyticIntegralWithinOnePercent) {
  const Case c = GetParam();
  const FabricMaterial material =
      MaterialFromKes(c.composite_denim ? testing::CompositeDenim() : testing::LoadDatabaseFabric(c.name));
  const double length = 0.38, width = 0.20, g = 9.81;
  const FabricModel model = BuildFabricModel(material, {length, width, 17, 15});
  ASSERT_EQ(model.triangles.size(), 448u);
  Placement pl;
  pl.axis_u_W = Eigen::Vector3d(0, 0, -1);  // warp hangs down
  pl.axis_v_W = Eigen::Vector3d(1, 0, 0);
  FabricState s = MakeRestState(model, pl);
  for (int p : testing::WarpRow(model, 0)) s.Fix(p);
  const auto bottom = testing::WarpRow(model, 16);

  StepOptions opt;
  opt.dt_s = 0.02;
  opt.cg_tolerance = 1e-9;
  opt.cg_max_iterations = 2000;
  FabricStepper stepper(model, opt);
  for (double load = 0.4; load < 2.45; load += 0.4) {
    s.external_force_W_N.setZero();
    AddEdgeLoad(model, bottom, Eigen::Vector3d(0, 0, -load), &s);
    testing::RunToRest(&stepper, &s, 20000, 1e-7);
    double z = 0.0;
    for (int p : bottom) z += s.x(p).z();
    const double simulated = -z / static_cast<double>(bottom.size()) - length;
    const double exact =
        testing::AnalyticHangingElongation(material.tensile_warp, length, width, material.density_kg_per_m2, load, g);
    const double rel = std::abs(simulated - exact) / exact;
    std::printf("[table] %s load %.1f N: simulated %.4f mm, analytic %.4f mm, error %.4f %%\n", c.label, load,
                1e3 * simulated, 1e3 * exact, 100 * rel);
    EXPECT_LE(rel, 0.01) << c.label << " at " << load << " N";
    EXPECT_EQ(s.diagnostics.nan_events, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Fabrics, TensileValidationTest,
    ::testing::Values(Case{"stiff_woven_composite_denim", true, ""},
                      Case{"soft_knit_wang2011_navy_sparkle_sweat", false, "wang2011_navy_sparkle_sweat"}),
    [](const ::testing::TestParamInfo<Case>& param_info) { return std::string(param_info.param.label); });

}  // namespace
}  // namespace haptex::textile
