// The dual layer with global_sim across a network (the global-link placement): patches and results
// arrive whole global steps late. Against the single-layer reference (the whole strip stepped at
// the local rate), a pinch that stretches a hanging strip and a finger rubbing a strip clamped at
// both ends stay close at every delay, and without the border extrapolation's limit they do not.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "libs/contact/patch_simulation.h"
#include "libs/dual_layer/dual_layer_sim.h"
#include "libs/dual_layer/pinch_stretch_strip.h"
#include "libs/textile/kes_material.h"
#include "tests/contact/contact_test_util.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::dual_layer {
namespace {

constexpr double kLocalDt_s = 0.001, kGlobalDt_s = 0.01;
using Fingers = std::function<std::array<contact::FingerInput, 2>(double t_s, const contact::ContactOptions&)>;
using ForceOf = std::function<double(const contact::ContactOutput&)>;

// The index finger presses 3 mm into the strip 5 cm below the clamp (0.3 s), then rubs +-8 mm
// along it at up to 5 cm/s.
std::array<contact::FingerInput, 2> PressAndRub(double t, const contact::ContactOptions& o) {
  const double r = o.index.radius_m + o.fabric_half_thickness_m;
  const double y = r + 0.002 - std::min(1.0, t / 0.3) * 0.005;
  const double x = t < 0.5 ? 0.0 : 0.008 * std::sin(2 * M_PI * (t - 0.5));
  return {contact::FingerInput{},
          contact::FingerInput{true, contact::PoseFacing(Eigen::Vector3d(x, y, -0.05), Eigen::Vector3d(0, -1, 0),
                                                         Eigen::Vector3d::UnitX())}};
}

struct Scenario {
  std::function<Strip()> strip;
  Fingers fingers;
  ForceOf force;
  contact::ContactOptions contact;
  double end_s;
};

Scenario Pinch(const textile::FabricMaterial& material) {
  contact::ContactOptions o;
  o.finger_fabric = {0.8, 0.6};
  return {[&material] { return PinchStretchStrip(material, 0.004); }, PinchStretchFingers,
          [](const contact::ContactOutput& a) { return a.finger[0].force_W_N.z() + a.finger[1].force_W_N.z(); }, o,
          2.5};
}

Scenario Rub(const textile::FabricMaterial& material) {
  contact::ContactOptions o;
  o.finger_fabric = {0.4, 0.2};
  return {[&material] {
            Strip s = PinchStretchStrip(material, 0.004);
            const int last = s.model.mesh.particles_warp() - 1;
            for (int j = 0; j < s.model.mesh.particles_weft(); ++j) s.state.Fix(s.model.mesh.Index(last, j));
            return s;
          },
          PressAndRub, [](const contact::ContactOutput& a) { return a.finger[1].force_W_N.norm(); }, o, 3.0};
}

std::vector<double> ReferenceForce(const Scenario& s) {
  Strip strip = s.strip();
  contact::PatchSimulation reference(std::move(strip.model), std::move(strip.state),
                                     contact::testing::LocalStep(kLocalDt_s), s.contact);
  std::vector<double> force;
  for (int k = 1; k * kLocalDt_s <= s.end_s + 1e-9; ++k) {
    const auto f = s.fingers(k * kLocalDt_s, s.contact);
    force.push_back(s.force(reference.Tick(f[0], f[1])));
  }
  return force;
}

struct Deviation {
  double peak_ratio = 0.0;       ///< dual layer's peak / reference's
  double rms_of_peak = 0.0;      ///< RMS difference / reference's peak
  std::uint32_t round_trip = 0;  ///< what global_sim measured at the end
};

Deviation Compare(const textile::FabricMaterial& material, const Scenario& s, const std::vector<double>& reference,
                  int delay_steps, bool extrapolate_in_full) {
  Strip strip = s.strip();
  DualLayerSim dual(material, std::move(strip.model), std::move(strip.state), kGlobalDt_s, kLocalDt_s, s.contact,
                    0.015);
  dual.set_link_delay_steps(delay_steps);
  dual.set_extrapolate_border_in_full(extrapolate_in_full);
  double peak = 0.0, peak_ref = 0.0, sum2 = 0.0;
  for (std::size_t k = 0; k < reference.size(); ++k) {
    const auto f = s.fingers(static_cast<double>(k + 1) * kLocalDt_s, s.contact);
    const double force = s.force(dual.Tick(f[0], f[1]));
    peak = std::max(peak, std::abs(force));
    peak_ref = std::max(peak_ref, std::abs(reference[k]));
    sum2 += (force - reference[k]) * (force - reference[k]);
  }
  return {peak / peak_ref, std::sqrt(sum2 / static_cast<double>(reference.size())) / peak_ref,
          dual.link_round_trip_steps()};
}

class DualLayerDelayTest : public ::testing::Test {
 protected:
  const textile::FabricMaterial material_ = textile::MaterialFromKes(textile::testing::CompositeDenim());
};

// Each way 0, 1, 2 and 5 global steps: up to a 110 ms round trip at 100 Hz.
TEST_F(DualLayerDelayTest, PinchAndStretchStaysNearTheReferenceAtEveryDelay) {
  const Scenario s = Pinch(material_);
  const std::vector<double> reference = ReferenceForce(s);
  for (int d : {0, 1, 2, 5}) {
    const Deviation dev = Compare(material_, s, reference, d, false);
    std::printf("[measured] pinch, %d steps each way (round trip measured %u): peak %.3f x, RMS %.2f %% of peak\n", d,
                dev.round_trip, dev.peak_ratio, 100 * dev.rms_of_peak);
    EXPECT_EQ(dev.round_trip, static_cast<std::uint32_t>(2 * d));
    EXPECT_LT(dev.peak_ratio, 1.25) << d << " steps each way";
    EXPECT_LT(dev.rms_of_peak, d == 0 ? 0.01 : 0.15) << d << " steps each way";
  }
}

TEST_F(DualLayerDelayTest, RubStaysNearTheReferenceAtEveryDelay) {
  const Scenario s = Rub(material_);
  const std::vector<double> reference = ReferenceForce(s);
  for (int d : {0, 1, 2, 5}) {
    const Deviation dev = Compare(material_, s, reference, d, false);
    std::printf("[measured] rub, %d steps each way: peak %.3f x, RMS %.2f %% of peak\n", d, dev.peak_ratio,
                100 * dev.rms_of_peak);
    EXPECT_LT(dev.peak_ratio, 1.5) << d << " steps each way";
    EXPECT_LT(dev.rms_of_peak, 0.15) << d << " steps each way";
  }
}

// The control: the border moved with global_sim's whole velocity (what the local layer did before
// the limit) amplifies the delayed loop, so the tests above can tell.
TEST_F(DualLayerDelayTest, ExtrapolatingTheBorderInFullThroughADelayedLinkOvershoots) {
  const Scenario s = Pinch(material_);
  const Deviation dev = Compare(material_, s, ReferenceForce(s), 2, true);
  std::printf("[measured] pinch, 2 steps each way, border extrapolated in full: peak %.3f x\n", dev.peak_ratio);
  EXPECT_GT(dev.peak_ratio, 1.5);
}

}  // namespace
}  // namespace haptex::dual_layer
