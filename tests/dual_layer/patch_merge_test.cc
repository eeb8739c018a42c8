// The coupling of the global fabric with the local patch (patch_merge.h): a PatchResult merged
// before the global step and held through it, and the velocity the next patch's border is moved
// with. The local layer's shape comes back once a global step; what the border ring does in
// response must not come back amplified at that period (the loop that fed the demo's 50 Hz force
// oscillation with a resting thumb), and a steadily moving cloth must keep its border velocity.
#include "libs/dual_layer/patch_merge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "libs/dual_layer/patch_cut.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::dual_layer {
namespace {

using V = Eigen::Vector3d;

constexpr double kDt = 0.01;

struct BorderMotion {
  double position_alternation_m = 0.0;                          // of the border ring's y over the global steps
  double extrapolated_alternation_m = 0.0;                      // of y + dt v_y: where local_contact takes the border
  double mean_sent_v_m_per_s = 0.0, mean_ring_v_m_per_s = 0.0;  // over the last steps
};

// A 20 x 20 cm denim at 1 cm hanging from its top edge in the plane y = 0. Every global step
// the 5 x 5 interior i, j in [8, 12] comes back from the local layer displaced along y by
// `interior_y(step)`; the patch [7, 13]^2 is cut after the step as global_sim does.
BorderMotion Couple(const std::function<double(int)>& interior_y) {
  const textile::FabricModel model =
      textile::BuildFabricModel(textile::MaterialFromKes(textile::testing::CompositeDenim()), {0.20, 0.20, 21, 21});
  textile::Placement placement;
  placement.origin_W = V(-0.10, 0.0, 0.0);
  placement.axis_u_W = V(0, 0, -1);
  placement.axis_v_W = V(1, 0, 0);
  textile::FabricState state = textile::MakeRestState(model, placement);
  for (int j = 0; j < 21; ++j) state.Fix(model.mesh.Index(0, j));
  const textile::FabricState rest = state;
  textile::StepOptions step_options;
  step_options.dt_s = kDt;
  textile::FabricStepper stepper(model, step_options);
  const RefinedGrid refined = MakeRefinedGrid(21, 21, 0);
  std::vector<int> merged;
  TwoStepVelocity cut_velocity;
  PatchResultData result;
  PatchData patch;
  std::vector<std::vector<double>> y, y_end;  // per step, per border particle
  std::vector<double> sent_v;
  const int steps = 80;
  for (int s = 0; s < steps; ++s) {
    result.Clear();
    for (int i = 8; i <= 12; ++i) {
      for (int j = 8; j <= 12; ++j) {
        const int p = model.mesh.Index(i, j);
        const V x = rest.x(p) + V(0, interior_y(s), 0);
        result.ids.push_back(static_cast<std::uint32_t>(p));
        for (int k = 0; k < 3; ++k) {
          result.x_W_m.push_back(x[k]);
          result.v_W_m_per_s.push_back(0.0);
          result.external_force_W_N.push_back(0.0);
        }
      }
    }
    EXPECT_EQ(MergePatchResult(result, static_cast<int>(refined.id_space()), &state, &merged), 0);
    EXPECT_EQ(merged.size(), 25u);
    stepper.Step(&state);
    ReleaseMerged(&state, &merged);
    const Eigen::VectorXd& v = cut_velocity.Update(state.v_W_m_per_s);
    CutPatch(model, state, v, {7, 13, 7, 13}, static_cast<std::uint64_t>(s + 1), static_cast<std::uint64_t>(s + 1), kDt,
             refined, &patch);
    std::vector<double> ys, ends;
    for (int k = 0; k < patch.num_particles; ++k) {
      if (patch.border[k] == 0) continue;
      ys.push_back(patch.x_W_m[3 * k + 1]);
      ends.push_back(patch.x_W_m[3 * k + 1] + kDt * patch.v_W_m_per_s[3 * k + 1]);
      if (s >= steps - 10) sent_v.push_back(patch.v_W_m_per_s[3 * k + 1]);
    }
    EXPECT_EQ(ys.size(), 24u);
    y.push_back(ys);
    y_end.push_back(ends);
  }
  BorderMotion m;
  int count = 0;
  for (int s = steps / 2; s + 1 < steps; ++s) {
    for (std::size_t b = 0; b < y[static_cast<std::size_t>(s)].size(); ++b) {
      const auto alternation = [&](const std::vector<std::vector<double>>& a) {
        return std::abs(a[static_cast<std::size_t>(s)][b] -
                        0.5 * (a[static_cast<std::size_t>(s - 1)][b] + a[static_cast<std::size_t>(s + 1)][b]));
      };
      m.position_alternation_m += alternation(y);
      m.extrapolated_alternation_m += alternation(y_end);
      ++count;
    }
  }
  m.position_alternation_m /= count;
  m.extrapolated_alternation_m /= count;
  for (double v : sent_v) m.mean_sent_v_m_per_s += v / static_cast<double>(sent_v.size());
  const std::size_t last = y.size() - 1;
  for (std::size_t b = 0; b < y[last].size(); ++b) {
    m.mean_ring_v_m_per_s += (y[last][b] - y[last - 10][b]) / (10 * kDt) / static_cast<double>(y[last].size());
  }
  return m;
}

// The local layer's interior alternating by 0.2 mm a step (the two interleaved chains): the border
// ring follows it, and where local_contact takes the border over the next step alternates no more
// than the ring itself does. (With the ring's last-step velocity, y + dt (y_s - y_(s-1)) / dt
// alternates three times as much: 3.0x here.)
TEST(PatchMergeTest, BorderTakesNoStepPeriodMotionFromTheMerge) {
  const BorderMotion m = Couple([](int s) { return s % 2 == 0 ? 0.0002 : 0.0; });
  std::printf("[merge] alternating interior: border ring alternates %.4f mm, extrapolated %.4f mm\n",
              1e3 * m.position_alternation_m, 1e3 * m.extrapolated_alternation_m);
  EXPECT_GT(m.position_alternation_m, 1e-6);
  EXPECT_LE(m.extrapolated_alternation_m, 1.2 * m.position_alternation_m);
}

// The local layer's interior moving steadily at 5 mm/s along the cloth's normal: the border ring
// comes along, and the patch border is sent with its velocity (the moving cloth the dual layer
// needs it for: DualLayerConsistencyTest).
TEST(PatchMergeTest, SteadilyMovingClothKeepsItsBorderVelocity) {
  const BorderMotion m = Couple([](int s) { return 0.005 * kDt * (s + 1); });
  std::printf("[merge] steady interior: border ring %.3f mm/s, sent %.3f mm/s\n", 1e3 * m.mean_ring_v_m_per_s,
              1e3 * m.mean_sent_v_m_per_s);
  EXPECT_GT(m.mean_ring_v_m_per_s, 0.002);
  EXPECT_NEAR(m.mean_sent_v_m_per_s, m.mean_ring_v_m_per_s, 0.05 * m.mean_ring_v_m_per_s);
}

// A newer result replaces the last; a malformed one merges and releases nothing; ids outside the
// id space and non-finite positions are rejected; particles global_sim prescribes stay its own.
// A particle of a result at x, at rest and unloaded.
void AddResultParticle(std::uint32_t id, const V& x, PatchResultData* r) {
  r->ids.push_back(id);
  for (int k = 0; k < 3; ++k) {
    r->x_W_m.push_back(x[k]);
    r->v_W_m_per_s.push_back(0.0);
    r->external_force_W_N.push_back(0.0);
  }
}

TEST(PatchMergeTest, MergesHoldsAndReleases) {
  const textile::FabricModel model =
      textile::BuildFabricModel(textile::MaterialFromKes(textile::testing::CompositeDenim()), {0.02, 0.02, 3, 3});
  textile::FabricState state = textile::MakeRestState(model);
  state.Fix(0);
  std::vector<int> merged;
  PatchResultData r;
  const auto add = [&r](std::uint32_t id, const V& x) { AddResultParticle(id, x, &r); };
  add(0, V(1, 1, 1));
  add(4, V(0.01, 0.01, 0.005));
  add(5, V(NAN, 0, 0));
  add(99, V::Zero());
  EXPECT_EQ(MergePatchResult(r, 20, &state, &merged), 2);
  ASSERT_EQ(merged, std::vector<int>{4});
  EXPECT_EQ(state.x(4), V(0.01, 0.01, 0.005));
  EXPECT_EQ(state.mode[4], textile::ParticleMode::kPrescribed);
  EXPECT_EQ(state.prescribed_v_W_m_per_s.segment<3>(12), V::Zero());
  EXPECT_EQ(state.x(0), V::Zero());  // the stand's
  PatchResultData bad = r;
  bad.ids.push_back(7);
  EXPECT_EQ(MergePatchResult(bad, 20, &state, &merged), -1);
  EXPECT_EQ(merged, std::vector<int>{4});
  r.Clear();
  add(7, V(0.0, 0.02, 0.001));
  EXPECT_EQ(MergePatchResult(r, 20, &state, &merged), 0);
  EXPECT_EQ(merged, std::vector<int>{7});
  EXPECT_EQ(state.mode[4], textile::ParticleMode::kFree);
  ReleaseMerged(&state, &merged);
  EXPECT_TRUE(merged.empty());
  EXPECT_EQ(state.mode[7], textile::ParticleMode::kFree);
  EXPECT_EQ(state.mode[0], textile::ParticleMode::kPrescribed);
}

// A step that no newer result reached holds the last result's particles again, where it put them,
// for at most max_held_steps steps after it; a newer result replaces it; a particle the scene fixed
// meanwhile is neither held nor freed.
TEST(PatchMergeTest, HoldsTheLastResultAgainUntilItIsTooOld) {
  const textile::FabricModel model =
      textile::BuildFabricModel(textile::MaterialFromKes(textile::testing::CompositeDenim()), {0.02, 0.02, 3, 3});
  textile::FabricState state = textile::MakeRestState(model);
  PatchResultData r;
  const auto add = [&r](std::uint32_t id, const V& x) { AddResultParticle(id, x, &r); };
  add(4, V(0.01, 0.01, 0.005));
  add(5, V(0.02, 0.01, 0.004));
  MergedInterior interior(2, model.num_particles);
  const auto held = [&state](int p) {
    return state.mode[static_cast<std::size_t>(p)] == textile::ParticleMode::kPrescribed;
  };
  ASSERT_EQ(interior.Merge(r, 20, &state), 0);
  interior.HoldBeforeStep(&state);  // a fresh result: held once, not twice
  EXPECT_TRUE(held(4) && held(5));
  interior.ReleaseAfterStep(&state);
  EXPECT_FALSE(held(4) || held(5));
  EXPECT_EQ(interior.steps_held_again(), 0u);
  state.Fix(5);  // the scene's own
  interior.HoldBeforeStep(&state);
  EXPECT_TRUE(held(4));
  EXPECT_EQ(state.x(4), V(0.01, 0.01, 0.005));
  EXPECT_EQ(state.v_W_m_per_s.segment<3>(12), V::Zero());
  interior.ReleaseAfterStep(&state);
  EXPECT_FALSE(held(4));
  EXPECT_TRUE(held(5));  // not freed: the hold did not take it
  EXPECT_EQ(interior.steps_held_again(), 1u);
  interior.HoldBeforeStep(&state);  // two steps after the result: too old
  EXPECT_FALSE(held(4));
  interior.ReleaseAfterStep(&state);
  EXPECT_EQ(interior.steps_held_again(), 1u);
  state.Free(5);
  r.Clear();
  add(7, V(0.0, 0.02, 0.001));
  ASSERT_EQ(interior.Merge(r, 20, &state), 0);
  interior.ReleaseAfterStep(&state);
  interior.HoldBeforeStep(&state);
  EXPECT_TRUE(held(7));
  EXPECT_FALSE(held(4) || held(5));
  interior.ReleaseAfterStep(&state);
}

}  // namespace
}  // namespace haptex::dual_layer
