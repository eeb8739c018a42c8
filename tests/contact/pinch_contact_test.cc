// PinchContact on its own: a flat patch squeezed between two capsules facing each other.
#include "libs/contact/pinch_contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "libs/contact/anchor_accumulator.h"
#include "libs/textile/fabric_model.h"
#include "tests/contact/contact_test_util.h"

namespace haptex::contact {
namespace {

using V = Eigen::Vector3d;

struct Squeeze {
  textile::FabricModel model;
  textile::FabricState state;
  ContactOptions options;
  FingerPose thumb, index;

  Squeeze()
      : model(textile::BuildFabricModel(testing::DatabaseMaterial("wang2011_black_denim_11oz"), {0.02, 0.02, 20, 20})) {
    textile::Placement placement;
    placement.origin_W = V(-0.01, -0.01, 0.0);
    state = textile::MakeRestState(model, placement);
    // Both skins 1 mm into the fabric's midsurface: the patch's middle lies in both fingers.
    const double r = options.thumb.radius_m + options.fabric_half_thickness_m - 0.001;
    thumb = testing::PoseFacing(V(0, 0, r), V(0, 0, -1), V::UnitX());
    index = testing::PoseFacing(V(0, 0, -r), V(0, 0, 1), V::UnitX());
  }
  // Prepares `pinch` and returns the springs it put on the particles.
  bool Prepare(PinchContact* pinch, textile::FabricState* springs_out) {
    std::vector<std::uint8_t> owned(static_cast<std::size_t>(model.num_particles), 0);
    AnchorAccumulator springs(model.num_particles);
    const bool active = pinch->Prepare(thumb, index, /*grip_N=*/2.0, {0.4, 0.2}, state, &owned, &springs);
    *springs_out = state;
    springs.WriteTo(springs_out);
    return active;
  }
};

TEST(PinchContactTest, ANonFiniteParticleDoesNotSpreadToItsNeighbours) {
  Squeeze s;
  PinchContact pinch(s.model, s.options);
  textile::FabricState springs;
  ASSERT_TRUE(s.Prepare(&pinch, &springs));
  // A particle in the middle of the pinch (every triangle around it deep in both fingers).
  const int bad = 10 * 20 + 10;
  s.state.x_W_m.segment<3>(3 * bad).setConstant(std::numeric_limits<double>::quiet_NaN());
  ASSERT_TRUE(s.Prepare(&pinch, &springs));
  int finite_springs = 0;
  for (int p = 0; p < s.model.num_particles; ++p) {
    if (p == bad) continue;
    EXPECT_TRUE(std::isfinite(springs.anchor_stiffness_N_per_m[p])) << p;
    EXPECT_TRUE(springs.anchor_W_m.segment<3>(3 * p).allFinite()) << p;
    finite_springs += springs.anchor_stiffness_N_per_m[p] > 0.0 ? 1 : 0;
  }
  EXPECT_GT(finite_springs, 20);  // the rest of the pinch still holds the fabric
  PinchResult result;
  pinch.Resolve(s.state, Eigen::MatrixX2d::Zero(s.model.num_particles, 2), &result);
  EXPECT_TRUE(std::isfinite(result.grip_N));
}

TEST(PinchContactTest, SamplesCarryOverToAFreshContactAndResetDropsThem) {
  Squeeze s;
  PinchContact pinch(s.model, s.options);
  textile::FabricState springs;
  ASSERT_TRUE(s.Prepare(&pinch, &springs));
  // Slide the fingers so that some samples slide and move their ideal positions.
  for (int k = 0; k < 20; ++k) {
    s.thumb.p_W_m.x() += 1e-4;
    s.index.p_W_m.x() += 1e-4;
    ASSERT_TRUE(s.Prepare(&pinch, &springs));
  }
  PinchContact fresh(s.model, s.options);
  ASSERT_EQ(fresh.num_samples(), pinch.num_samples());
  ASSERT_EQ(fresh.samples_per_triangle(), s.options.pinch_samples_per_edge * s.options.pinch_samples_per_edge);
  int active = 0, sliding = 0;
  for (int i = 0; i < pinch.num_samples(); ++i) {
    const PinchContact::SampleState a = pinch.sample(i);
    fresh.SetSample(i, a);
    const PinchContact::SampleState b = fresh.sample(i);
    EXPECT_EQ(b.active, a.active);
    EXPECT_EQ(b.sliding, a.sliding);
    EXPECT_EQ(b.ideal_C, a.ideal_C);
    active += a.active ? 1 : 0;
    sliding += a.active && a.sliding ? 1 : 0;
  }
  EXPECT_GT(active, 100);
  EXPECT_GT(sliding, 0);
  // The fresh contact continues where the old one was: the same springs next tick.
  textile::FabricState springs_old, springs_fresh;
  ASSERT_TRUE(s.Prepare(&pinch, &springs_old));
  ASSERT_TRUE(s.Prepare(&fresh, &springs_fresh));
  EXPECT_EQ(springs_fresh.anchor_W_m, springs_old.anchor_W_m);
  EXPECT_EQ(springs_fresh.anchor_stiffness_N_per_m, springs_old.anchor_stiffness_N_per_m);

  pinch.Reset();
  for (int i = 0; i < pinch.num_samples(); ++i) EXPECT_FALSE(pinch.sample(i).active) << i;
}

}  // namespace
}  // namespace haptex::contact
