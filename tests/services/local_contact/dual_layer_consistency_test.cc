// Dual layer against a single-layer reference (issue 6): the same scripted pinch and stretch of a
// hanging strip, once with the whole strip stepped at the local rate in one simulation, once
// through the dual layer (global at 100 Hz, patches at 1 kHz with hand-offs). Final shape within
// 2 mm RMS; the fingers' force within 10 % of the reference's peak at every tick. (Point by point
// the dual layer's force runs 0.12-0.16 N above the reference during the pull: 21 % early in the
// pull, 3.4 % at the end; the cause of that offset is not found yet. The test prints both.)

#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "libs/contact/patch_simulation.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/kes_material.h"
#include "tests/services/local_contact/dual_layer_harness.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::local_contact {
namespace {

using V = Eigen::Vector3d;

contact::FingerPose Facing(const V& centre, const V& pad_normal) {
  contact::FingerPose pose;
  pose.p_W_m = centre;
  pose.R_WF.col(0) = V::UnitX();
  pose.R_WF.col(2) = pad_normal;
  pose.R_WF.col(1) = pad_normal.cross(V::UnitX());
  return pose;
}

struct Strip {
  textile::FabricModel model;
  textile::FabricState state;
};

Strip MakeStrip(const textile::FabricMaterial& material) {
  const double width = 0.03, length = 0.08;
  Strip s{textile::BuildFabricModel(material, {length, width, 41, 16}), {}};
  textile::Placement placement;  // warp hangs down from z = 0, weft across along x
  placement.origin_W = V(-0.5 * width, 0.0, 0.0);
  placement.axis_u_W = V(0, 0, -1);
  placement.axis_v_W = V(1, 0, 0);
  s.state = textile::MakeRestState(s.model, placement);
  for (int j = 0; j < 16; ++j) s.state.Fix(s.model.mesh.Index(0, j));
  return s;
}

// Pinch at 6 cm below the clamp: approach (0.3 s), hold, pull down 3 mm (1.5 s), hold.
std::array<contact::FingerInput, 2> Script(double t, const contact::ContactOptions& o) {
  const double r = o.thumb.radius_m + o.fabric_half_thickness_m;
  const double y = r + 0.003 - std::min(1.0, t / 0.3) * 0.0055;
  const double dz = 0.003 * std::clamp((t - 0.5) / 1.5, 0.0, 1.0);
  return {contact::FingerInput{true, Facing(V(0, -y, -0.06 - dz), V(0, 1, 0))},
          contact::FingerInput{true, Facing(V(0, y, -0.06 - dz), V(0, -1, 0))}};
}

TEST(DualLayerConsistencyTest, MatchesSingleLayerReference) {
  const textile::FabricMaterial material =
      textile::MaterialFromKes(textile::testing::CompositeDenim());
  contact::ContactOptions o;
  o.finger_fabric = {0.8, 0.6};
  textile::StepOptions local;
  local.dt_s = 0.001;
  local.cg_tolerance = 1e-3;
  local.cg_max_iterations = 100;
  local.preconditioner = textile::Preconditioner::kBlockJacobi;

  Strip ref_strip = MakeStrip(material);
  contact::PatchSimulation reference(std::move(ref_strip.model), std::move(ref_strip.state), local, o);
  Strip dual_strip = MakeStrip(material);
  testing::DualLayerHarness dual(material, std::move(dual_strip.model), std::move(dual_strip.state),
                                 0.01, 0.001, o, 0.005);

  const double t_end = 2.5;
  double worst_force = 0.0, peak_ref = 0.0, worst_abs = 0.0;
  for (int k = 1; k * 0.001 <= t_end + 1e-9; ++k) {
    const auto f = Script(k * 0.001, o);
    const contact::ContactOutput& a = reference.Tick(f[0], f[1]);
    const double fa = a.finger[0].force_W_N.z() + a.finger[1].force_W_N.z();
    const contact::ContactOutput& b = dual.Tick(f[0], f[1]);
    const double fb = b.finger[0].force_W_N.z() + b.finger[1].force_W_N.z();
    peak_ref = std::max(peak_ref, std::abs(fa));
    if (k % 250 == 0) {
      std::printf("[dual] t %.2f s force ref %.4f N dual %.4f N, states %s %s\n", k * 0.001, fa, fb,
                  contact::ToString(a.state), contact::ToString(b.state));
    }
    worst_abs = std::max(worst_abs, std::abs(fb - fa));
    // Once the pull has built a force (over 20 % of its final 3.6 N), compare point by point.
    if (std::abs(fa) > 0.7) worst_force = std::max(worst_force, std::abs(fb - fa) / std::abs(fa));
  }
  // The dual layer's fabric is its global state (patch results merged in).
  const Eigen::VectorXd& xa = reference.state().x_W_m;
  const Eigen::VectorXd& xb = dual.global_state().x_W_m;
  const double rms = std::sqrt((xa - xb).squaredNorm() / (static_cast<double>(xa.size()) / 3.0));
  std::printf("[dual] shape RMS %.3f mm, largest force difference %.3f N = %.2f %% of the peak %.3f N "
              "(point by point, beyond 0.7 N: %.2f %%), %d hand-offs\n",
              1e3 * rms, worst_abs, 100 * worst_abs / peak_ref, peak_ref, 100 * worst_force, dual.handoffs());
  EXPECT_GT(peak_ref, 3.0);
  EXPECT_GT(dual.handoffs(), 200);
  EXPECT_LE(rms, 0.002);
  EXPECT_LE(worst_abs, 0.10 * peak_ref);
}

}  // namespace
}  // namespace haptex::local_contact
