// Paper Fig. 9 and issue 5: an artificial user presses a finger onto a fabric (a patch held taut
// in a frame) and rubs it. The finger's F_T/F_N (of the force the device gets) stays below mu_s
// while the contact sticks, peaks within mu_s +- 5 % ([0.38, 0.42] for mu_s = 0.4) when it breaks
// away, holds mu_d +- 0.02 while it slides, and the contact sticks again when the finger stops.
// For several coefficient pairs.
//
// This holds because friction is decided for the finger as a whole (finger_fabric_contact.h).
// With per-particle stick-slip the peak is 0.23 for mu_s = 0.4: pressing pre-loads the held points
// radially and the lightly loaded rim slips first, so the particles slip one after another and the
// finger never reaches mu_s.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "libs/contact/patch_simulation.h"
#include "tests/contact/contact_test_util.h"

namespace haptex::contact {
namespace {

struct RubCase {
  double mu_s, mu_d;
};

struct RubTrace {
  std::vector<double> t, ratio, friction_ratio, normal, slip, cone_mu;
  std::vector<ContactState> state;
};

// Press 2 mm into a 3 x 3 cm patch, hold, rub 8 mm along +y at 10 mm/s, stop, hold.
constexpr double kPressEnd = 0.2, kRubStart = 0.3, kRubEnd = 1.1, kEnd = 1.4;

RubTrace RunRub(const RubCase& c, bool verbose) {
  ContactOptions options;
  options.finger_fabric = {c.mu_s, c.mu_d};
  auto sim = testing::MakeFlatPatch(testing::DatabaseMaterial("wang2011_black_denim_11oz"), 0.03, 31, options,
                                    testing::LocalStep(), 0.01);
  const double r = options.thumb.radius_m + options.fabric_half_thickness_m;
  const Eigen::Vector3d above(0, 0.0, r + 0.002), pressed(0, 0.0, r - 0.002), rubbed(0, 0.008, r - 0.002);
  RubTrace trace;
  const double dt = sim->dt_s();
  for (int k = 1; k * dt <= kEnd + 1e-9; ++k) {
    const double t = k * dt;
    Eigen::Vector3d p = t < kRubStart ? testing::Ramp(above, pressed, t, 0.0, kPressEnd)
                                      : testing::Ramp(pressed, rubbed, t, kRubStart, kRubEnd);
    FingerInput thumb{true, testing::PoseFacing(p, Eigen::Vector3d(0, 0, -1), Eigen::Vector3d::UnitX())};
    const ContactOutput& out = sim->Tick(thumb, FingerInput{});
    const FingerContactOutput& f = out.finger[kThumb];
    trace.t.push_back(t);
    trace.ratio.push_back(f.normal_force_N > 0 ? f.tangential_force_N / f.normal_force_N : 0.0);
    trace.normal.push_back(f.normal_force_N);
    trace.cone_mu.push_back(f.friction_cone_mu);
    trace.state.push_back(out.state);
    trace.slip.push_back(out.evidence.slip_fraction);
    trace.friction_ratio.push_back(f.friction_normal_N > 0 ? f.friction_tangential_N / f.friction_normal_N : 0.0);
    if (verbose && k % 100 == 0) {
      std::printf("[fig9] t %.2f s state %-2s F_N %.3f N F_T/F_N %.3f (the law's %.3f), %d particles\n", t,
                  ToString(out.state), f.normal_force_N, trace.ratio.back(), trace.friction_ratio.back(),
                  f.contact_particles);
    }
  }
  return trace;
}

class RubFrictionTest : public ::testing::TestWithParam<RubCase> {};

TEST_P(RubFrictionTest, StickSlideStick) {
  const RubCase c = GetParam();
  const RubTrace tr = RunRub(c, true);
  // The finger slips when its friction does (each finger sticks or slides as a whole: the slip
  // fraction is 0 or 1); the state names it V within the classifier's filter time.
  double stick_max = 0.0, slip_t = -1.0, state_v_t = -1.0, peak = 0.0, peak_t = -1.0, rub_max = 0.0;
  double slide_min = 1e9, slide_max = 0.0, slide_friction_min = 1e9, slide_friction_max = 0.0;
  double law_max = 0.0;  // the friction law's F^T/F^N over the whole rub
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    const double t = tr.t[i];
    if (t <= kRubStart || t >= kRubEnd) continue;
    rub_max = std::max(rub_max, tr.ratio[i]);
    law_max = std::max(law_max, tr.friction_ratio[i]);
    if (state_v_t < 0.0 && tr.state[i] == ContactState::kV) state_v_t = t;
    if (slip_t < 0.0 && tr.slip[i] > 0.5) {
      slip_t = t;
      for (std::size_t j = i > 3 ? i - 3 : 0; j < std::min(tr.t.size(), i + 4); ++j) {
        std::printf("[fig9]   t %.3f s state %-2s F_T/F_N %.4f\n", tr.t[j], ToString(tr.state[j]), tr.ratio[j]);
      }
    }
    if (slip_t < 0.0) stick_max = std::max(stick_max, tr.ratio[i]);
    // The peak: the largest ratio up to 20 ms after the contact turned dynamic.
    if ((slip_t < 0.0 || t <= slip_t + 0.02) && tr.ratio[i] > peak) {
      peak = tr.ratio[i];
      peak_t = t;
    }
    if (slip_t > 0.0 && t > slip_t + 0.2) {
      EXPECT_EQ(tr.state[i], ContactState::kV) << "t " << t;
      slide_min = std::min(slide_min, tr.ratio[i]);
      slide_max = std::max(slide_max, tr.ratio[i]);
      slide_friction_min = std::min(slide_friction_min, tr.friction_ratio[i]);
      slide_friction_max = std::max(slide_friction_max, tr.friction_ratio[i]);
    }
  }
  std::printf(
      "[fig9] mu_s %.2f mu_d %.2f: stick max %.3f, peak %.3f at %.3f s, slip at %.3f s (named "
      "V at %.3f s), sliding %.3f..%.3f (the law's %.4f..%.4f, its peak %.4f)\n",
      c.mu_s, c.mu_d, stick_max, peak, peak_t, slip_t, state_v_t, slide_min, slide_max, slide_friction_min,
      slide_friction_max, law_max);
  ASSERT_GT(slip_t, kRubStart) << "never slid";
  ASSERT_GE(state_v_t, slip_t) << "named V before it slid";
  EXPECT_LE(state_v_t - slip_t, 0.015) << "named V too late";
  EXPECT_GT(slip_t, kRubStart + 0.002) << "no stick phase";
  // Sticking: below mu_s. Breaking away: mu_s +- 5 %. Never above that while rubbing.
  EXPECT_LT(stick_max, c.mu_s);
  EXPECT_GE(peak, 0.95 * c.mu_s);
  EXPECT_LE(peak, 1.05 * c.mu_s);
  EXPECT_LE(rub_max, 1.05 * c.mu_s);
  // Sliding: mu_d +- 0.02 for the finger. The friction law itself holds the contacts to mu_d
  // while they slide and breaks away at mu_s: never above it.
  EXPECT_NEAR(slide_min, c.mu_d, 0.02);
  EXPECT_NEAR(slide_max, c.mu_d, 0.02);
  EXPECT_NEAR(slide_friction_min, c.mu_d, 1e-6);
  EXPECT_NEAR(slide_friction_max, c.mu_d, 1e-6);
  EXPECT_NEAR(law_max, c.mu_s, 1e-6);
  // The cone handed to the bridge: mu_s wide, wider only where the finger's own ratio is (it holds
  // every force the contact gives), none before the finger touches.
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    if (tr.normal[i] <= 0.0) {
      EXPECT_EQ(tr.cone_mu[i], 0.0) << "t " << tr.t[i];
      continue;
    }
    EXPECT_DOUBLE_EQ(tr.cone_mu[i], std::max(c.mu_s, tr.ratio[i])) << "t " << tr.t[i];
  }
  // The finger stops: the contact sticks again and holds what it had.
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    if (tr.t[i] < kRubEnd + 0.05) continue;
    EXPECT_EQ(tr.state[i], ContactState::kIV) << "t " << tr.t[i];
    EXPECT_NEAR(tr.ratio[i], c.mu_d, 0.02) << "t " << tr.t[i];
  }
}

INSTANTIATE_TEST_SUITE_P(Coefficients, RubFrictionTest,
                         ::testing::Values(RubCase{0.4, 0.2}, RubCase{0.6, 0.3}, RubCase{0.3, 0.25}, RubCase{1.0, 0.8}),
                         [](const ::testing::TestParamInfo<RubCase>& param_info) {
                           const RubCase& c = param_info.param;
                           return "mu_s_" + std::to_string(static_cast<int>(100 * c.mu_s)) + "_mu_d_" +
                                  std::to_string(static_cast<int>(100 * c.mu_d));
                         });

}  // namespace
}  // namespace haptex::contact
