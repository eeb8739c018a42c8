// Dual layer against a single-layer reference (issue 6): the same scripted pinch and stretch of a
// hanging strip, once with the whole strip stepped at the local rate in one simulation, once
// through the dual layer (global at 100 Hz, patches at 1 kHz with hand-offs), with the scenes'
// default patch margin (15 mm). Final shape within 2 mm RMS; the fingers' force within 10 % of the
// reference's at every tick once the pull has built a force, and within 10 % of its peak at every
// tick. With a 5 mm margin the patch border (held where global_sim put it, a global step behind)
// sits close to the pinch and the force runs up to 20 % above the reference early in the pull
// (3 % at 15 mm, 0.5 % at 30 mm): the margin is an accuracy dial (bench/dual_layer sweep).

#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "libs/contact/patch_simulation.h"
#include "libs/dual_layer/dual_layer_sim.h"
#include "libs/dual_layer/pinch_stretch_strip.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::dual_layer {
namespace {

struct Comparison {
  double shape_rms_m = 0.0, largest_force_difference_N = 0.0, peak_reference_N = 0.0;
  double pointwise_beyond_0p7N = 0.0;  // largest |dual - ref| / |ref| once |ref| > 0.7 N
  int handoffs = 0;
};

// The scripted pinch and stretch through the dual layer (patches refined `refinement_levels`
// times) and through the single-layer reference, both from a 2 mm strip.
Comparison Compare(int refinement_levels, double patch_margin_m) {
  const textile::FabricMaterial material = textile::MaterialFromKes(textile::testing::CompositeDenim());
  contact::ContactOptions o;
  o.finger_fabric = {0.8, 0.6};
  textile::StepOptions local;
  local.dt_s = 0.001;
  local.cg_tolerance = 1e-3;
  local.cg_max_iterations = 100;
  local.preconditioner = textile::Preconditioner::kBlockJacobi;

  Strip ref_strip = PinchStretchStrip(material, 0.002);
  contact::PatchSimulation reference(std::move(ref_strip.model), std::move(ref_strip.state), local, o);
  Strip dual_strip = PinchStretchStrip(material, 0.002);
  DualLayerSim dual(material, std::move(dual_strip.model), std::move(dual_strip.state), 0.01, 0.001, o, patch_margin_m,
                    refinement_levels);

  Comparison c;
  const double t_end = 2.5;
  for (int k = 1; k * 0.001 <= t_end + 1e-9; ++k) {
    const auto f = PinchStretchFingers(k * 0.001, o);
    const contact::ContactOutput& a = reference.Tick(f[0], f[1]);
    const double fa = a.finger[0].force_W_N.z() + a.finger[1].force_W_N.z();
    const contact::ContactOutput& b = dual.Tick(f[0], f[1]);
    const double fb = b.finger[0].force_W_N.z() + b.finger[1].force_W_N.z();
    c.peak_reference_N = std::max(c.peak_reference_N, std::abs(fa));
    if (k % 250 == 0) {
      std::printf("[dual r%d] t %.2f s force ref %.4f N dual %.4f N, states %s %s\n", refinement_levels, k * 0.001, fa,
                  fb, contact::ToString(a.state), contact::ToString(b.state));
    }
    c.largest_force_difference_N = std::max(c.largest_force_difference_N, std::abs(fb - fa));
    // Once the pull has built a force (over 20 % of its final 3.6 N), compare point by point.
    if (std::abs(fa) > 0.7)
      c.pointwise_beyond_0p7N = std::max(c.pointwise_beyond_0p7N, std::abs(fb - fa) / std::abs(fa));
  }
  // The dual layer's fabric is its global state (patch results merged in).
  const Eigen::VectorXd& xa = reference.state().x_W_m;
  const Eigen::VectorXd& xb = dual.global_state().x_W_m;
  c.shape_rms_m = std::sqrt((xa - xb).squaredNorm() / (static_cast<double>(xa.size()) / 3.0));
  c.handoffs = dual.handoffs();
  std::printf(
      "[dual r%d] shape RMS %.3f mm, largest force difference %.3f N = %.2f %% of the peak %.3f N "
      "(point by point, beyond 0.7 N: %.2f %%), %d hand-offs\n",
      refinement_levels, 1e3 * c.shape_rms_m, c.largest_force_difference_N,
      100 * c.largest_force_difference_N / c.peak_reference_N, c.peak_reference_N, 100 * c.pointwise_beyond_0p7N,
      c.handoffs);
  return c;
}

// Refinement 0: the fabric's own 2 mm cells; 1: 1 mm patch cells on the 2 mm fabric (the local layer
// resolves the contact finer, the result stays the same fabric's).
class DualLayerConsistencyTest : public ::testing::TestWithParam<int> {};

TEST_P(DualLayerConsistencyTest, MatchesSingleLayerReference) {
  const Comparison c = Compare(GetParam(), 0.015);
  EXPECT_GT(c.peak_reference_N, 3.0);
  EXPECT_GT(c.handoffs, 200);
  EXPECT_LE(c.shape_rms_m, 0.002);
  EXPECT_LE(c.largest_force_difference_N, 0.10 * c.peak_reference_N);
  EXPECT_LE(c.pointwise_beyond_0p7N, 0.10);
}

INSTANTIATE_TEST_SUITE_P(PatchRefinement, DualLayerConsistencyTest, ::testing::Values(0, 1),
                         [](const auto& param_info) { return "refinement" + std::to_string(param_info.param); });

}  // namespace
}  // namespace haptex::dual_layer
