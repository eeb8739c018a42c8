// Numerical stability of the contact layer at the extremes: a 20 N squeeze, friction from 0 to
// 2, a finger at 1 m/s, a 5 cm teleport into the fabric, the lightest and the stiffest fabric and
// one 10x stiffer than any real one. Never NaN, forces bounded by the configured cap, no
// tunnelling through the fabric at <= 0.5 m/s.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "libs/contact/haptic_step_options.h"
#include "libs/contact/patch_simulation.h"
#include "libs/textile/fabric_model.h"
#include "tests/contact/contact_test_util.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::contact {
namespace {

enum class Motion { kPressAndRub, kTeleport, kSqueeze };

struct Extreme {
  const char* label;
  const char* fabric;
  double stiffness_scale;
  double mu_s, mu_d;
  double speed_m_per_s;
  Motion motion;
  bool check_tunnelling;
};

void PrintTo(const Extreme& e, std::ostream* os) { *os << e.label; }

// The tests' tight solve (block Jacobi to 1e-3) and the haptic tick's (local_contact's).
enum class Solver { kTight, kHaptic };

class ContactExtremesTest : public ::testing::TestWithParam<std::tuple<Extreme, Solver>> {};

TEST_P(ContactExtremesTest, FiniteBoundedNoTunnelling) {
  const Extreme e = std::get<0>(GetParam());
  const bool haptic = std::get<1>(GetParam()) == Solver::kHaptic;
  textile::FabricMaterial material = testing::DatabaseMaterial(e.fabric);
  if (e.stiffness_scale != 1.0) material = textile::testing::ScaleStiffness(material, e.stiffness_scale);
  ContactOptions options;
  options.finger_fabric = {e.mu_s, e.mu_d};
  auto sim = testing::MakeFlatPatch(material, 0.04, 21, options,
                                    haptic ? HapticPatchStepOptions(0.001) : testing::LocalStep());
  const double r = options.thumb.radius_m + options.fabric_half_thickness_m;
  const double dt = sim->dt_s();
  const Eigen::Vector3d down(0, 0, -1);
  double max_force = 0.0, deepest = 0.0;
  int tunnelled = 0;
  Eigen::Vector3d thumb(0, 0, r + 0.005);
  for (int k = 1; k <= 500; ++k) {
    const double t = k * dt;
    Eigen::Vector3d index(0, 0, -(r + 0.005));
    bool with_index = false;
    switch (e.motion) {
      case Motion::kPressAndRub: {
        // Press 8 mm at the given speed, then rub 8 mm along +y and back.
        const double press = std::min(0.008, e.speed_m_per_s * t);
        const double rub_t = std::max(0.0, t - 0.008 / e.speed_m_per_s);
        const double rub = 0.008 * std::sin(std::min(1.0, rub_t * e.speed_m_per_s / 0.008) * M_PI);
        thumb = Eigen::Vector3d(0, rub, r + 0.005 - press);
        break;
      }
      case Motion::kTeleport:
        // Hovering 5 cm above, then in one tick 3 mm deep in the fabric.
        thumb = t < 0.1 ? Eigen::Vector3d(0, 0, 0.05) : Eigen::Vector3d(0, 0, r - 0.003);
        break;
      case Motion::kSqueeze: {
        // Thumb above, index below; squeeze until their centres coincide: > 20 N.
        const double s = std::min(1.0, t / 0.3);
        thumb = Eigen::Vector3d(0, 0, r + 0.002 - s * (0.008 + 0.002 + options.fabric_half_thickness_m));
        index = -thumb;
        with_index = true;
        break;
      }
    }
    const ContactOutput& out = sim->Tick({true, testing::PoseFacing(thumb, down, Eigen::Vector3d::UnitX())},
                                         {with_index, testing::PoseFacing(index, -down, Eigen::Vector3d::UnitX())});
    ASSERT_TRUE(sim->state().x_W_m.allFinite()) << "t " << t;
    ASSERT_TRUE(sim->state().v_W_m_per_s.allFinite()) << "t " << t;
    for (const auto& f : out.finger) {
      ASSERT_TRUE(f.force_W_N.allFinite());
      ASSERT_TRUE(f.stiffness_W_N_per_m.allFinite());
      max_force = std::max(max_force, f.force_W_N.norm());
      EXPECT_LE(f.force_W_N.norm(), options.max_finger_force_N * (1 + 1e-12));
      EXPECT_LE(f.stiffness_W_N_per_m.norm(), std::sqrt(3.0) * options.max_stiffness_N_per_m + 1e-9);
    }
    if (e.check_tunnelling && e.motion == Motion::kPressAndRub) {
      // Every particle under the finger stays below it: none has passed the capsule's axis.
      for (int p = 0; p < sim->model().num_particles; ++p) {
        const Eigen::Vector3d x = sim->state().x(p);
        const Eigen::Vector3d rel = x - thumb;
        if (std::abs(rel.x()) < 0.006 && std::abs(rel.y()) < 0.003 && rel.z() > 0.0) ++tunnelled;
        const double depth = r - std::hypot(rel.y(), rel.z());
        if (std::abs(rel.x()) < 0.006) deepest = std::max(deepest, depth);
      }
    }
  }
  if (e.motion == Motion::kSqueeze) {
    // The fingers end with coincident centres (the deepest overlap there is): 1.25 N/mm x 16.6 mm.
    EXPECT_NEAR(sim->solver().output().pinch.grip_N, options.finger_finger_normal_N_per_m * 2 * r, 1e-6);
    EXPECT_GE(sim->solver().output().pinch.grip_N, 20.0);
  }
  std::printf(
      "[extremes] %s (%s solve): max finger force %.3f N, deepest particle %.2f mm, tunnelled %d, "
      "step status %s, clamps %lld\n",
      e.label, haptic ? "haptic" : "tight", max_force, 1e3 * deepest, tunnelled,
      textile::ToString(sim->last_step().status), static_cast<long long>(sim->solver().diagnostics().force_clamps));
  EXPECT_EQ(tunnelled, 0);
  if (e.check_tunnelling) {
    EXPECT_LT(deepest, 0.5 * r);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Matrix, ContactExtremesTest,
    ::testing::Combine(
        ::testing::Values(
            Extreme{"squeeze_20N", "wang2011_black_denim_11oz", 1, 0.4, 0.2, 0.1, Motion::kSqueeze, false},
            Extreme{"mu_0", "wang2011_black_denim_11oz", 1, 0.0, 0.0, 0.05, Motion::kPressAndRub, true},
            Extreme{"mu_2", "wang2011_black_denim_11oz", 1, 2.0, 1.5, 0.05, Motion::kPressAndRub, true},
            Extreme{"speed_0p5", "wang2011_black_denim_11oz", 1, 0.4, 0.2, 0.5, Motion::kPressAndRub, true},
            Extreme{"speed_1", "wang2011_black_denim_11oz", 1, 0.4, 0.2, 1.0, Motion::kPressAndRub, false},
            Extreme{"teleport_5cm", "wang2011_black_denim_11oz", 1, 0.4, 0.2, 0.0, Motion::kTeleport, false},
            Extreme{"lightest", "wang2011_gray_interlock", 1, 0.4, 0.2, 0.5, Motion::kPressAndRub, true},
            Extreme{"stiffest", "wang2011_royal_target", 1, 0.4, 0.2, 0.5, Motion::kPressAndRub, true},
            Extreme{"stiffest_x10", "wang2011_royal_target", 10, 0.4, 0.2, 0.5, Motion::kPressAndRub, true}),
        ::testing::Values(Solver::kTight, Solver::kHaptic)),
    [](const ::testing::TestParamInfo<std::tuple<Extreme, Solver>>& param_info) {
      return std::string(std::get<0>(param_info.param).label) +
             (std::get<1>(param_info.param) == Solver::kHaptic ? "_haptic" : "_tight");
    });

}  // namespace
}  // namespace haptex::contact
