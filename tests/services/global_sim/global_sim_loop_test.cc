// GlobalSimLoop in process: FingerStates and PatchResults in, and what it sends out (LocalPatch to
// local_contact, ClothFrames to the viewer); and no allocation in its warmed-up step.

#include "services/global_sim/global_sim_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "libs/codec/cloth_positions.h"
#include "libs/codec/message_conversion.h"
#include "services/local_contact/local_contact_codec.h"
#include "tests/support/allocation_counter.h"
#include "tests/support/captured_outbox.h"
#include "tests/support/test_paths.h"
#include "tests/support/wrap_envelope.h"

namespace haptex::global_sim {
namespace {

using V = Eigen::Vector3d;
constexpr services::PeerId kLocal = 0, kViewer = 1;
constexpr double kDt = 0.01;

// A 10 x 10 cm denim at 5 mm hanging from a stand at the origin (plane y = 0, along -z).
scene::LoadedScene TestScene() {
  const scene::FabricDatabase db(haptex::testing::SourceDir() + "/data/fabrics");
  return scene::ParseScene(R"(name: "loop"
fabric { database_name: "wang2011_black_denim_11oz" }
cloth { width_m: 0.1 height_m: 0.1 particles_u: 21 particles_v: 21 }
fingers { finger: FINGER_THUMB }
fingers { finger: FINGER_INDEX }
device { mock {} }
rates { cloth_frame_hz: 25 }
)",
                           "loop", db);
}

v1::FingerStates ThumbAt(const V& p_W_m, bool device_ok = true) {
  v1::FingerStates states;
  states.set_device_ok(device_ok);
  v1::FingerState* f = states.add_fingers();
  f->set_finger(v1::FINGER_THUMB);
  codec::ToMessage(p_W_m, f->mutable_position_w_m());
  codec::ToMessage(p_W_m, f->mutable_predicted_position_w_m());
  return states;
}

class GlobalSimLoopTest : public ::testing::Test {
 protected:
  GlobalSimLoopTest()
      : scene_(TestScene()), health_("global_sim"), loop_(scene_, 1.0 / kDt, {kLocal, kViewer}, &health_) {}

  void Step(services::Outbox& out) {
    loop_.Update(step_ * kDt, kDt);
    loop_.Write(out);
    ++step_;
  }
  std::uint64_t Counter(const std::string& name) {
    for (const auto& c : health_.Build(0.0).counters()) {
      if (c.name() == name) return c.value();
    }
    ADD_FAILURE() << "no counter " << name;
    return 0;
  }

  scene::LoadedScene scene_;
  runtime::HealthReporter health_;
  GlobalSimLoop loop_;
  int step_ = 0;
  std::uint64_t sequence_ = 0;
};

TEST_F(GlobalSimLoopTest, ClothFramesAtTheirRateAndPatchesOnlyNearAFinger) {
  haptex::testing::CapturedOutbox out;
  for (int s = 0; s < 20; ++s) Step(out);
  EXPECT_TRUE(out.Of<v1::LocalPatch>(kLocal).empty()) << "no finger: nothing to cut";
  const auto frames = out.Of<v1::ClothFrame>(kViewer);
  EXPECT_EQ(frames.size(), 5u);  // 25 Hz over 0.2 s at a 10 ms step
  EXPECT_EQ(frames.back().particles_u(), 21u);
  EXPECT_EQ(frames.back().chunk_count(), 1u);
  EXPECT_EQ(frames.back().patch_u_end(), frames.back().patch_u_begin()) << "no finger: no patch to show";
  ASSERT_EQ(frames.back().position_q_size(), 3 * 441);
  std::vector<float> cloth_W_m(3 * 441);
  ASSERT_EQ(codec::DecodeClothPositions(frames.back(), cloth_W_m.data(), cloth_W_m.size()), 3 * 441);
  for (int p = 0; p < 441; ++p) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_NEAR(cloth_W_m[3 * p + k], loop_.state().x(p)[k], 0.5 * codec::kClothQuantumM + 1e-7) << p;
    }
  }

  // the thumb near the cloth's centre: a patch every step around it
  out.Clear();
  loop_.Read(haptex::testing::WrapEnvelope(ThumbAt(V(0, 0.009, -0.05)), ++sequence_), step_ * kDt);
  for (int s = 0; s < 3; ++s) Step(out);
  const auto patches = out.Of<v1::LocalPatch>(kLocal);
  ASSERT_EQ(patches.size(), 3u);
  const v1::LocalPatch& p = patches.back();
  EXPECT_EQ(p.global_step(), 23u);
  EXPECT_EQ(p.global_dt_s(), kDt);
  EXPECT_GT(p.patch_id(), patches.front().patch_id());
  int border = 0;
  for (bool b : p.is_border()) border += b;
  EXPECT_GT(border, 0);
  EXPECT_LT(border, p.particle_ids_size());
  dual_layer::PatchData copy(4096);
  EXPECT_EQ(local_contact::CopyPatch(p, 441, &copy), local_contact::PatchCopy::kOk) << "local_contact can build it";

  // the device lost: no patch
  out.Clear();
  loop_.Read(haptex::testing::WrapEnvelope(ThumbAt(V(0, 0.009, -0.05), false), ++sequence_), step_ * kDt);
  Step(out);
  EXPECT_TRUE(out.Of<v1::LocalPatch>(kLocal).empty());
  EXPECT_EQ(Counter("patches_sent"), 3u);
}

// The viewer is shown the patch global_sim cut at the frame's step: the rectangle its particles lie in.
TEST_F(GlobalSimLoopTest, ClothFramesCarryThePatchRectangleCutAtTheirStep) {
  haptex::testing::CapturedOutbox out;
  loop_.Read(haptex::testing::WrapEnvelope(ThumbAt(V(0, 0.009, -0.05)), ++sequence_), step_ * kDt);
  for (int s = 0; s < 8; ++s) Step(out);  // two frame periods
  const auto frames = out.Of<v1::ClothFrame>(kViewer);
  ASSERT_FALSE(frames.empty());
  const v1::ClothFrame& f = frames.back();
  ASSERT_LT(f.patch_u_begin(), f.patch_u_end());
  ASSERT_LT(f.patch_v_begin(), f.patch_v_end());
  EXPECT_LT(f.patch_u_end() - f.patch_u_begin(), 21u) << "a patch, not the whole cloth";
  const v1::LocalPatch& patch = out.Of<v1::LocalPatch>(kLocal).back();
  int inside = 0;
  for (const std::uint32_t id : patch.particle_ids()) {
    if (id >= 441) continue;  // refined particles are the patch's own
    const std::uint32_t i = id % 21, j = id / 21;
    EXPECT_TRUE(i >= f.patch_u_begin() && i < f.patch_u_end() && j >= f.patch_v_begin() && j < f.patch_v_end()) << id;
    ++inside;
  }
  EXPECT_EQ(inside, static_cast<int>((f.patch_u_end() - f.patch_u_begin()) * (f.patch_v_end() - f.patch_v_begin())));
}

// Without a viewer, ClothFrames go only into the recording, and only when the scene asks for them:
// a run replays with its cloth (haptex view) without a viewer having watched it.
TEST(GlobalSimLoopRecordingTest, ClothFramesAreRecordedWithoutAViewerWhenTheSceneAsks) {
  for (const bool asked : {false, true}) {
    scene::LoadedScene scene = TestScene();
    scene.scene.mutable_recording()->set_cloth_frames(asked);
    runtime::HealthReporter health("global_sim");
    GlobalSimLoop loop(scene, 1.0 / kDt, {kLocal, std::nullopt}, &health);
    haptex::testing::CapturedOutbox out;
    for (int s = 0; s < 20; ++s) {
      loop.Update(s * kDt, kDt);
      loop.Write(out);
    }
    EXPECT_EQ(out.Count<v1::ClothFrame>(), 0u) << "nobody to send them to";
    EXPECT_EQ(out.Recorded<v1::ClothFrame>(), asked ? 5u : 0u) << "25 Hz over 0.2 s, recorded when asked";
  }
}

// The global link's round trip, counted in global_sim's own steps from a patch's cut to the merge
// of a result computed on it, travels with every patch to local_contact.
TEST_F(GlobalSimLoopTest, PatchesCarryTheGlobalLinksRoundTrip) {
  haptex::testing::CapturedOutbox out;
  loop_.Read(haptex::testing::WrapEnvelope(ThumbAt(V(0, 0.009, -0.05)), ++sequence_), step_ * kDt);
  for (int s = 0; s < 6; ++s) Step(out);
  ASSERT_FALSE(out.Of<v1::LocalPatch>(kLocal).empty());
  EXPECT_EQ(out.Of<v1::LocalPatch>(kLocal).back().link_round_trip_steps(), 0u) << "no result yet: immediate";
  const int p = 10 + 21 * 10;
  v1::PatchResult result;
  result.set_patch_id(1);
  result.set_global_step(static_cast<std::uint64_t>(step_) - 3);  // computed on the patch cut 3 steps ago
  result.add_particle_ids(static_cast<std::uint32_t>(p));
  for (int k = 0; k < 3; ++k) {
    result.add_position_w_m(loop_.state().x(p)[k]);
    result.add_velocity_w_m_per_s(0.0);
    result.add_external_force_w_n(0.0);
  }
  loop_.Read(haptex::testing::WrapEnvelope(result, ++sequence_), step_ * kDt);
  out.Clear();
  Step(out);
  const auto patches = out.Of<v1::LocalPatch>(kLocal);
  ASSERT_EQ(patches.size(), 1u);
  EXPECT_EQ(patches.back().link_round_trip_steps(), 3u);
  dual_layer::PatchData copy(4096);
  ASSERT_EQ(local_contact::CopyPatch(patches.back(), 441, &copy), local_contact::PatchCopy::kOk);
  EXPECT_EQ(copy.link_round_trip_steps, 3u) << "local_contact reads it";
}

TEST_F(GlobalSimLoopTest, ResultsAreHeldThroughTheStepAndBadOnesCounted) {
  haptex::testing::CapturedOutbox out;
  for (int s = 0; s < 5; ++s) Step(out);
  const int p = 10 + 21 * 10;  // the centre
  const V pushed = loop_.state().x(p) + V(0, -0.002, 0);
  v1::PatchResult result;
  result.set_patch_id(1);
  result.add_particle_ids(static_cast<std::uint32_t>(p));
  for (int k = 0; k < 3; ++k) {
    result.add_position_w_m(pushed[k]);
    result.add_velocity_w_m_per_s(0.0);
    result.add_external_force_w_n(0.0);
  }
  loop_.Read(haptex::testing::WrapEnvelope(result, ++sequence_), step_ * kDt);
  Step(out);
  EXPECT_EQ(loop_.state().x(p), pushed) << "held where local_contact put it through the step";
  EXPECT_EQ(loop_.state().mode[static_cast<std::size_t>(p)], textile::ParticleMode::kFree) << "released after it";
  // no newer result: held there again in every step up to kLastResultHoldMax_s after it, then free
  const int held_steps = static_cast<int>(std::ceil(dual_layer::kLastResultHoldMax_s / kDt - 1e-9));
  for (int s = 1; s < held_steps; ++s) {
    Step(out);
    ASSERT_EQ(loop_.state().x(p), pushed) << "step " << s << " after the result";
  }
  EXPECT_EQ(Counter("patch_results_held_again"), static_cast<std::uint64_t>(held_steps - 1));
  Step(out);
  EXPECT_NE(loop_.state().x(p), pushed) << "free again: it moves";

  v1::PatchResult short_arrays = result;
  short_arrays.mutable_position_w_m()->RemoveLast();
  loop_.Read(haptex::testing::WrapEnvelope(short_arrays, ++sequence_), step_ * kDt);
  v1::PatchResult outside = result;
  outside.set_particle_ids(0, 100000);
  loop_.Read(haptex::testing::WrapEnvelope(outside, ++sequence_), step_ * kDt);
  v1::PatchResult nan = result;
  nan.set_position_w_m(1, std::nan(""));
  loop_.Read(haptex::testing::WrapEnvelope(nan, ++sequence_), step_ * kDt);
  Step(out);
  EXPECT_TRUE(loop_.state().x_W_m.allFinite());
  EXPECT_EQ(Counter("patch_results_merged"), 3u);  // the good one, and the two with one bad particle each
  EXPECT_EQ(Counter("patch_results_rejected"), 3u);
}

TEST_F(GlobalSimLoopTest, WarmedUpStepDoesNotAllocate) {
  if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting is off in this build";
  haptex::testing::CapturedOutbox out;
  out.capture = false;
  const v1::Envelope states = haptex::testing::WrapEnvelope(ThumbAt(V(0, 0.009, -0.05)), 1);
  loop_.Read(states, 0.0);
  for (int s = 0; s < 30; ++s) Step(out);  // warm-up
  v1::PatchResult result;
  for (int p = 200; p < 230; ++p) {
    result.add_particle_ids(static_cast<std::uint32_t>(p));
    for (int k = 0; k < 3; ++k) {
      result.add_position_w_m(loop_.state().x(p)[k]);
      result.add_velocity_w_m_per_s(0.0);
      result.add_external_force_w_n(0.0);
    }
  }
  std::vector<v1::Envelope> results;
  for (int s = 0; s < 21; ++s)
    results.push_back(haptex::testing::WrapEnvelope(result, 2 + static_cast<std::uint64_t>(s)));
  loop_.Read(results.back(), 0.0);
  Step(out);
  haptex::testing::AllocationCounter counter;
  for (int s = 0; s < 20; ++s) {
    loop_.Read(results[static_cast<std::size_t>(s)], step_ * kDt);
    Step(out);
  }
  EXPECT_EQ(counter.count(), 0);
  EXPECT_EQ(out.Count<v1::LocalPatch>(), 51u);
}

}  // namespace
}  // namespace haptex::global_sim
