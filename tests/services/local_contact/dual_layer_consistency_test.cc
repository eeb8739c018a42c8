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

  testing::Strip ref_strip = testing::PinchStretchStrip(material, 0.002);
  contact::PatchSimulation reference(std::move(ref_strip.model), std::move(ref_strip.state), local, o);
  testing::Strip dual_strip = testing::PinchStretchStrip(material, 0.002);
  testing::DualLayerHarness dual(material, std::move(dual_strip.model), std::move(dual_strip.state),
                                 0.01, 0.001, o, 0.005);

  const double t_end = 2.5;
  double worst_force = 0.0, peak_ref = 0.0, worst_abs = 0.0;
  for (int k = 1; k * 0.001 <= t_end + 1e-9; ++k) {
    const auto f = testing::PinchStretchFingers(k * 0.001, o);
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
