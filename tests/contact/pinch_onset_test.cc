// Closing a pinch on hanging fabric in closed loop, as the demo does it: the thumb presses the
// fabric's front, then the index comes to the back. Each fingertip is the mock GRAB's fingertip (a
// mass pulled by the artificial user's spring toward its target, pushed by the rendered force
// F0 + K dx at 5 kHz); the contact runs at 1 kHz. The state must not chatter between the pinch
// (VIII/IX) and the one-finger states once the fingers squeeze the fabric (paper Table 1, with
// hysteresis). The thumb's own contact holds the fabric on its skin, one half-thickness off the
// midsurface; a pinch that counted that fabric as outside would enter and leave as the index closes
// slowly (docs/contact.md, "The models").

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "libs/contact/patch_simulation.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/kes_material.h"
#include "tests/contact/contact_test_util.h"

namespace haptex::contact {
namespace {

using V = Eigen::Vector3d;

// The mock controller's fingertip (libs/device/mock_grab_controller.h defaults).
struct Fingertip {
  V p_W_m, v_W_m_per_s{V::Zero()};
  static constexpr double kMass_kg = 0.1, kUserStiffness_N_per_m = 300.0, kUserDamping_N_s_per_m = 4.0,
                          kDeviceDamping_N_s_per_m = 0.5;
  void Step(const V& target_W_m, const V& force_W_N, double dt_s) {
    const V a = (kUserStiffness_N_per_m * (target_W_m - p_W_m) - kUserDamping_N_s_per_m * v_W_m_per_s -
                 kDeviceDamping_N_s_per_m * v_W_m_per_s + force_W_N) /
                kMass_kg;
    v_W_m_per_s += dt_s * a;
    p_W_m += dt_s * v_W_m_per_s;
  }
};

bool Pinched(ContactState s) { return s == ContactState::kVIII || s == ContactState::kIX; }

struct Closing {
  double press_m;        // how far past the fabric plane each finger's target goes
  double index_close_s;  // how long the index takes from 10 mm off its skin to there
};

class PinchOnsetTest : public ::testing::TestWithParam<Closing> {};

TEST_P(PinchOnsetTest, ClosingAPinchOnHangingFabricDoesNotChatter) {
  const double press = GetParam().press_m, index_close_s = GetParam().index_close_s;
  // 5 x 5 cm of the demo's denim hanging from its top edge in the x-z plane, 2.5 mm spacing; the
  // thumb at its front (-y), the index at its back (+y), 2.5 cm below the clamp.
  const textile::FabricMaterial material = testing::DatabaseMaterial("wang2011_black_denim_11oz");
  const double size = 0.05;
  const int n = 21;
  textile::FabricModel model = textile::BuildFabricModel(material, {size, size, n, n});
  textile::Placement placement;
  placement.origin_W = V(-0.5 * size, 0.0, 0.0);
  placement.axis_u_W = V(0, 0, -1);
  placement.axis_v_W = V(1, 0, 0);
  textile::FabricState state = textile::MakeRestState(model, placement);
  for (int j = 0; j < n; ++j) state.Fix(model.mesh.Index(0, j));
  const ContactOptions options;
  PatchSimulation sim(std::move(model), std::move(state), testing::LocalStep(), options);

  const double r = options.thumb.radius_m + options.fabric_half_thickness_m;
  const double z = -0.025, start = 0.010;
  auto pose = [&](const V& p, bool thumb) { return testing::PoseFacing(p, V(0, thumb ? 1 : -1, 0), V::UnitX()); };
  // targets: the thumb presses `press` past the fabric plane by t = 0.3 s, the index from 0.5 s
  // on, then both hold for 0.2 s
  auto target = [&](double t, bool thumb) {
    const double s = thumb ? std::clamp(t / 0.3, 0.0, 1.0) : std::clamp((t - 0.5) / index_close_s, 0.0, 1.0);
    const double y = (r + start) - s * (start + press);
    return V(0, thumb ? -y : y, z);
  };
  Fingertip thumb{target(0.0, true)}, index{target(0.0, false)};

  const double dt = sim.dt_s();
  const int substeps = 5;  // the bridge and the fingertips at 5 kHz
  std::vector<ContactState> states;
  std::vector<double> thumb_force;
  int pinch_entries = 0, pinch_exits = 0;
  bool was_pinched = false;
  for (int k = 1; k * dt <= 0.7 + index_close_s + 1e-9; ++k) {
    const double t = k * dt;
    const ContactOutput& out = sim.Tick({true, pose(thumb.p_W_m, true)}, {true, pose(index.p_W_m, false)});
    const bool pinched = Pinched(out.state);
    pinch_entries += pinched && !was_pinched;
    pinch_exits += !pinched && was_pinched;
    was_pinched = pinched;
    states.push_back(out.state);
    thumb_force.push_back(out.finger[0].force_W_N.norm());
    const V x0_thumb = thumb.p_W_m, x0_index = index.p_W_m;
    const FingerContactOutput f_thumb = out.finger[0], f_index = out.finger[1];
    for (int s = 1; s <= substeps; ++s) {
      const double ts = t + s * dt / substeps;
      thumb.Step(target(ts, true), f_thumb.force_W_N + f_thumb.stiffness_W_N_per_m * (thumb.p_W_m - x0_thumb),
                 dt / substeps);
      index.Step(target(ts, false), f_index.force_W_N + f_index.stiffness_W_N_per_m * (index.p_W_m - x0_index),
                 dt / substeps);
    }
    ASSERT_TRUE(thumb.p_W_m.allFinite() && index.p_W_m.allFinite()) << "at " << t << " s";
  }
  // After the pinch is first reached, how often did it get lost, and by how much did the force
  // fall back?
  const auto first = std::find_if(states.begin(), states.end(), Pinched);
  ASSERT_NE(first, states.end()) << "the fingers never pinched the fabric";
  const std::size_t k_pinch = static_cast<std::size_t>(first - states.begin());
  double worst_drop = 0.0, peak = 0.0;
  for (std::size_t k = k_pinch; k < thumb_force.size(); ++k) {
    peak = std::max(peak, thumb_force[k]);
    worst_drop = std::max(worst_drop, peak - thumb_force[k]);
  }
  std::printf(
      "[measured] press %.0f mm, index closing in %.1f s: pinch reached at %.3f s; entries %d, "
      "exits %d; thumb force at end %.2f N, peak %.2f N, largest fall below the running peak "
      "%.2f N\n",
      press * 1e3, index_close_s, (k_pinch + 1) * dt, pinch_entries, pinch_exits, thumb_force.back(), peak, worst_drop);
  EXPECT_EQ(pinch_entries, 1) << "the pinch chattered";
  EXPECT_EQ(pinch_exits, 0);
  EXPECT_TRUE(Pinched(states.back()));
  // the grip through the fabric (1.25 N/mm) against the user's 300 N/m: about 0.27 N per mm
  EXPECT_GT(thumb_force.back(), 0.2 * press * 1e3) << "the held pinch must be felt";
}

INSTANTIATE_TEST_SUITE_P(PressAndSpeed, PinchOnsetTest,
                         ::testing::Values(Closing{0.001, 0.3}, Closing{0.001, 1.0}, Closing{0.002, 0.3},
                                           Closing{0.002, 1.0}, Closing{0.004, 0.3}, Closing{0.004, 1.0}),
                         [](const ::testing::TestParamInfo<Closing>& param_info) {
                           return "Press" + std::to_string(static_cast<int>(param_info.param.press_m * 1e3 + 0.5)) +
                                  "mmIndexIn" +
                                  std::to_string(static_cast<int>(param_info.param.index_close_s * 10 + 0.5)) + "ds";
                         });

}  // namespace
}  // namespace haptex::contact
