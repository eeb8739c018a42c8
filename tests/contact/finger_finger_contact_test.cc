// States II/III: the paper's finger-finger proxy (1.25 N/mm normal spring, Coulomb stick-slip).

#include "libs/contact/finger_finger_contact.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/contact/contact_test_util.h"

namespace haptex::contact {
namespace {

ContactOptions Spheres() {
  ContactOptions o;
  o.thumb.length_m = 0.0;
  o.index.length_m = 0.0;
  o.finger_finger = {0.4, 0.2};
  return o;
}

FingerPose At(const Eigen::Vector3d& p) {
  FingerPose pose;
  pose.p_W_m = p;
  return pose;
}

TEST(FingerFingerContactTest, OneMillimetrePenetrationGives1p25Newton) {
  const ContactOptions o = Spheres();
  FingerFingerContact contact(o);
  const double d = o.thumb.radius_m + o.index.radius_m - 0.001;
  const FingerFingerResult r = contact.Update(At({0, 0, 0}), At({0, d, 0}), 0.0, o.finger_finger, true);
  ASSERT_TRUE(r.touching);
  EXPECT_NEAR(r.normal_N, 1.25, 0.0125);
  EXPECT_NEAR(r.force_on_index_W_N.y(), 1.25, 0.0125);  // pushes the index away from the thumb
  EXPECT_NEAR(r.normal_W.y(), 1.0, 1e-12);
  EXPECT_NEAR(r.stiffness_index_W_N_per_m(1, 1), -1250.0, 1e-6);
}

TEST(FingerFingerContactTest, CapsulesUseTheirClosestPoints) {
  ContactOptions o;
  FingerFingerContact contact(o);
  // Crossed capsules, axes along x and z, 1 mm overlap.
  FingerPose index = At({0, o.thumb.radius_m + o.index.radius_m - 0.001, 0});
  index.R_WF = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const FingerFingerResult r = contact.Update(At({0, 0, 0}), index, 0.0, o.finger_finger, false);
  EXPECT_NEAR(r.normal_N, 1.25, 1e-9);
}

TEST(FingerFingerContactTest, NoForceWhenApart) {
  const ContactOptions o = Spheres();
  FingerFingerContact contact(o);
  const FingerFingerResult r = contact.Update(At({0, 0, 0}), At({0, 0.0161, 0}), 0.0, o.finger_finger, true);
  EXPECT_FALSE(r.touching);
  EXPECT_EQ(r.force_on_index_W_N, Eigen::Vector3d::Zero());
}

TEST(FingerFingerContactTest, SticksUntilMuStaticThenSlidesAtMuDynamicThenSticks) {
  const ContactOptions o = Spheres();
  FingerFingerContact contact(o);
  const double d = o.thumb.radius_m + o.index.radius_m - 0.001;  // F_N = 1.25 N
  double peak = 0.0, first_slip_x = -1.0;
  bool slid = false;
  FingerFingerResult r;
  // The index slides along x at 1 um per tick for 2 mm, then stops.
  for (int k = 0; k <= 2000; ++k) {
    const double x = 1e-6 * k;
    // Keep the centre distance (so the penetration) constant while moving tangentially.
    r = contact.Update(At({0, 0, 0}), At({x, std::sqrt(d * d - x * x), 0}), 0.0, o.finger_finger, true);
    const double ratio = r.tangential_N / r.normal_N;
    if (!r.sliding) {
      EXPECT_LE(ratio, 0.4 + 1e-9) << "stick above mu_s at x " << x;
      peak = std::max(peak, ratio);
    } else {
      if (!slid) first_slip_x = x;
      slid = true;
      EXPECT_NEAR(ratio, 0.2, 0.02) << x;
    }
  }
  EXPECT_TRUE(slid);
  EXPECT_GE(peak, 0.38);
  EXPECT_LE(peak, 0.42);
  // The slip starts where the tangential spring reaches mu_s F_N: when the touching point on the
  // thumb's surface has moved 0.4 x 1.25 N / 1250 N/m = 0.4 mm along it.
  EXPECT_NEAR(first_slip_x, d * std::sin(0.0004 / o.thumb.radius_m), 2e-6);
  // Stopping: the contact sticks again at the force it had.
  const double x_end = 0.002;
  r = contact.Update(At({0, 0, 0}), At({x_end, std::sqrt(d * d - x_end * x_end), 0}), 0.0, o.finger_finger, true);
  EXPECT_FALSE(r.sliding);
  EXPECT_NEAR(r.tangential_N / r.normal_N, 0.2, 0.02);
}

}  // namespace
}  // namespace haptex::contact
