// Paper Fig. 10: an artificial user pinches a hanging strip between thumb and index (states
// VIII/IX) and pulls it down. The tangential force on the fingers against the strip's elongation
// must follow the fabric's own tensile curve (the analytic strip: F = width x f(strain)) within
// 10 % over the curve's nonlinear range, and the pinch must hold (stick) throughout.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "libs/contact/patch_simulation.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/kes_material.h"
#include "tests/contact/contact_test_util.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::contact {
namespace {

TEST(PinchStretchTest, TangentialForceFollowsTensileCurve) {
  // A KES fabric with a nonlinear tensile curve (LT 0.655): the test-only composite denim.
  const textile::FabricMaterial material = textile::MaterialFromKes(textile::testing::CompositeDenim());
  const double width = 0.012, length = 0.05, spacing = 0.002;
  const int nu = static_cast<int>(std::lround(length / spacing)) + 1;
  const int nv = static_cast<int>(std::lround(width / spacing)) + 1;
  textile::FabricModel model = textile::BuildFabricModel(material, {length, width, nu, nv});
  textile::Placement placement;  // warp hangs down from the clamp at z = 0, weft across along x
  placement.origin_W = Eigen::Vector3d(-0.5 * width, 0.0, 0.0);
  placement.axis_u_W = Eigen::Vector3d(0, 0, -1);
  placement.axis_v_W = Eigen::Vector3d(1, 0, 0);
  textile::FabricState state = textile::MakeRestState(model, placement);
  for (int j = 0; j < nv; ++j) state.Fix(model.mesh.Index(0, j));
  const int pinch_row = nu - 5;
  const double pinch_u = pinch_row * spacing;

  ContactOptions options;
  options.finger_fabric = {0.8, 0.6};  // a firm grip: the pinch must not slip in this test
  PatchSimulation sim(std::move(model), std::move(state), testing::LocalStep(), options);

  const double r = options.thumb.radius_m + options.fabric_half_thickness_m;
  const double overlap = 0.0032;  // per finger: grip 1.25 N/mm x 6.4 mm = 8 N
  const double pull = 0.0024;     // 4.8 % strain of the part above the pinch
  auto pose = [&](double y, double dz, bool thumb) {
    return testing::PoseFacing(Eigen::Vector3d(0, y, -pinch_u - dz), Eigen::Vector3d(0, thumb ? 1 : -1, 0),
                               Eigen::Vector3d::UnitX());
  };
  const double t_grasp = 0.3, t_pull0 = 0.5, t_pull1 = 3.5;
  double worst = 0.0, rows = 0.0;
  bool stuck = true;
  std::vector<ContactState> seen;
  const double dt = sim.dt_s();
  for (int k = 1; k * dt <= t_pull1 + 1e-9; ++k) {
    const double t = k * dt;
    const double y = r + 0.003 - std::clamp(t / t_grasp, 0.0, 1.0) * (0.003 + overlap);
    const double dz = pull * std::clamp((t - t_pull0) / (t_pull1 - t_pull0), 0.0, 1.0);
    const ContactOutput& out = sim.Tick({true, pose(-y, dz, true)}, {true, pose(y, dz, false)});
    if (seen.empty() || seen.back() != out.state) seen.push_back(out.state);
    if (t < t_pull0) continue;
    ASSERT_TRUE(out.state == ContactState::kVIII || out.state == ContactState::kIX) << ToString(out.state);
    if (out.state == ContactState::kIX) stuck = false;
    // Elongation of the strip above the pinch row, and the force the fingers feel along it.
    double z = 0.0;
    for (int j = 0; j < nv; ++j) z += sim.state().x(sim.model().mesh.Index(pinch_row, j)).z();
    const double strain = (-z / nv - pinch_u) / pinch_u;
    const double force_up = out.finger[kThumb].force_W_N.z() + out.finger[kIndex].force_W_N.z();
    const double analytic = width * material.tensile_warp.Value(strain);
    if (k % 250 == 0) {
      std::printf("[fig10] t %.2f s strain %.3f %% force %.4f N analytic %.4f N state %s samples %d\n", t, 100 * strain,
                  force_up, analytic, ToString(out.state), out.pinch.samples);
    }
    // Compare where the curve is nonlinear (beyond 1 % strain; the toe below is tiny in N).
    if (strain > 0.01 && t > t_pull0 + 0.2) {
      worst = std::max(worst, std::abs(force_up - analytic) / analytic);
      rows += 1;
    }
  }
  std::printf("[fig10] worst relative error %.4f over %.0f samples\n", worst, rows);
  EXPECT_GT(rows, 100);
  EXPECT_LE(worst, 0.10);
  EXPECT_TRUE(stuck) << "the pinch slipped";
  // The grasp went through one-finger and two-finger contact into the pinch.
  EXPECT_NE(std::find(seen.begin(), seen.end(), ContactState::kVIII), seen.end());
}

}  // namespace
}  // namespace haptex::contact
