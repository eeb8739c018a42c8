// LocalContactLoop in process: FingerStates and a LocalPatch in, and what it sends out (ForceModel
// to the bridge, TouchTrace to tactile, PatchResult to global_sim), with the patch built by a
// PatchBuilder the test runs itself; and no allocation in its warmed-up tick.

#include "services/local_contact/local_contact_loop.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libs/codec/message_conversion.h"
#include "libs/dual_layer/patch_cut.h"
#include "libs/dual_layer/refined_grid.h"
#include "libs/scene/cloth_setup.h"
#include "libs/scene/scene_contact.h"
#include "services/global_sim/global_sim_codec.h"
#include "tests/support/allocation_counter.h"
#include "tests/support/captured_outbox.h"
#include "tests/support/test_paths.h"
#include "tests/support/wrap_envelope.h"

namespace haptex::local_contact {
namespace {

using V = Eigen::Vector3d;
constexpr services::PeerId kBridge = 0, kGlobal = 1, kTactile = 2;

// A 10 x 10 cm denim at 5 mm hanging from a stand at the origin (in the plane y = 0, along -z),
// touched by the thumb from its front (+y).
scene::LoadedScene TestScene() {
  const scene::FabricDatabase db(haptex::testing::SourceDir() + "/data/fabrics");
  return scene::ParseScene(R"(name: "loop"
fabric { database_name: "wang2011_black_denim_11oz" }
cloth { width_m: 0.1 height_m: 0.1 particles_u: 21 particles_v: 21 }
fingers { finger: FINGER_THUMB }
fingers { finger: FINGER_INDEX }
device { mock {} }
)",
                           "loop", db);
}

// The thumb `depth_m` into the cloth's centre, pad facing the cloth; the index finger far away.
v1::FingerStates Thumb(double depth_m, std::uint64_t controller_sequence, bool device_ok = true) {
  const contact::ContactOptions o;
  const V centre(0.0, o.thumb.radius_m + o.fabric_half_thickness_m - depth_m, -0.05);
  const contact::FingerPose thumb = contact::PoseFacing(centre, V(0, -1, 0), V::UnitX());
  const contact::FingerPose index = contact::PoseFacing(V(0, -0.05, -0.05), V(0, 1, 0), V::UnitX());
  v1::FingerStates states;
  states.set_controller_sequence(controller_sequence);
  states.set_device_ok(device_ok);
  for (const auto& [finger, pose] : {std::pair{v1::FINGER_THUMB, thumb}, std::pair{v1::FINGER_INDEX, index}}) {
    v1::FingerState* f = states.add_fingers();
    f->set_finger(finger);
    codec::ToMessage(pose.p_W_m, f->mutable_position_w_m());
    codec::ToMessage(pose.p_W_m, f->mutable_predicted_position_w_m());
    codec::ToMessage(Eigen::Quaterniond(pose.R_WF), f->mutable_orientation_wf());
  }
  return states;
}

class LocalContactLoopTest : public ::testing::Test {
 protected:
  LocalContactLoopTest()
      : scene_(TestScene()),
        setup_(scene::MakeClothSetup(scene_)),
        refined_(dual_layer::MakeRefinedGrid(21, 21, 0)),
        builder_(PatchBuildSpec{setup_.material, setup_.model_options, scene::LocalStepOptions(scene_.scene, 1000.0),
                                scene::ContactOptionsFromScene(scene_), static_cast<int>(refined_.id_space()), 4096},
                 PatchBuilder::Threading::kCallerRuns),
        health_("local_contact"),
        loop_(LocalContactConfig{1000.0, {true, true}, 0.010}, {kBridge, kGlobal, kTactile, std::nullopt}, &builder_,
              &health_) {}

  // The patch global_sim would cut around the thumb from the cloth at rest.
  v1::LocalPatch Patch(std::uint64_t id, std::uint64_t global_step) const {
    const scene::ClothInstance cloth = scene::MakeClothInstance(setup_);
    std::array<dual_layer::FingerSphere, 2> spheres{};
    spheres[0] = dual_layer::SweptSphere(V(0, 0.008, -0.05), V(0, 0.008, -0.05), V::Zero(), 0.0143, 0.01, 0.015);
    dual_layer::PatchData data;
    dual_layer::CutPatch(cloth.model, cloth.state, cloth.state.v_W_m_per_s,
                         dual_layer::FindPatchRect(cloth.model, cloth.state, spheres), id, global_step, 0.01, refined_,
                         &data);
    v1::LocalPatch patch;
    global_sim::ToMessage(data, &patch);
    return patch;
  }

  // One tick at time k ms with the thumb `depth_m` in.
  void Tick(int k, double depth_m, services::Outbox& out) {
    loop_.Read(
        haptex::testing::WrapEnvelope(Thumb(depth_m, static_cast<std::uint64_t>(k)), static_cast<std::uint64_t>(k)),
        k * 0.001);
    loop_.Update(k * 0.001, 0.001);
    loop_.Write(out);
  }

  std::uint64_t Counter(const std::string& name) {
    for (const auto& c : health_.Build(0.0).counters()) {
      if (c.name() == name) return c.value();
    }
    ADD_FAILURE() << "no counter " << name;
    return 0;
  }

  scene::LoadedScene scene_;
  scene::ClothSetup setup_;
  dual_layer::RefinedGrid refined_;
  PatchBuilder builder_;
  runtime::HealthReporter health_;
  LocalContactLoop loop_;
};

TEST_F(LocalContactLoopTest, ZeroForceUntilAPatchArrivesThenItPushesTheThumbBackAndReports) {
  haptex::testing::CapturedOutbox out;
  Tick(1, 0.002, out);
  auto models = out.Of<v1::ForceModel>(kBridge);
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].based_on_controller_sequence(), 1u);
  ASSERT_EQ(models[0].fingers_size(), 2);
  EXPECT_EQ(models[0].fingers(0).finger(), v1::FINGER_THUMB);
  EXPECT_EQ(codec::ToEigen(models[0].fingers(0).f0_w_n()), V::Zero()) << "no fabric yet";
  EXPECT_EQ(models[0].fingers(0).ttl_s(), 0.010);
  EXPECT_EQ(models[0].fingers(0).stiffness_w_n_per_m_size(), 9);
  EXPECT_TRUE(out.Of<v1::TouchTrace>(kTactile).empty());
  EXPECT_TRUE(out.Of<v1::PatchResult>(kGlobal).empty());

  // a patch: queued, built (by the test, standing in for the builder thread), swapped in
  loop_.Read(haptex::testing::WrapEnvelope(Patch(1, 7), 1000), 0.001);
  EXPECT_TRUE(builder_.RunOnce());
  out.Clear();
  for (int k = 2; k <= 31; ++k) Tick(k, 0.002, out);
  EXPECT_EQ(loop_.counters().patch_handoffs, 1u);
  models = out.Of<v1::ForceModel>(kBridge);
  ASSERT_EQ(models.size(), 30u);
  const v1::FingerForceModel& thumb = models.back().fingers(0);
  EXPECT_GT(thumb.f0_w_n().y(), 0.005) << "the cloth pushes the thumb back out (+y)";
  // the friction cone the bridge keeps its extrapolation in: about the push, at least mu_s wide
  EXPECT_NEAR(thumb.friction_cone_axis_w().y(), 1.0, 0.05);
  EXPECT_GE(thumb.friction_cone_mu(), scene::ContactOptionsFromScene(scene_).finger_fabric.mu_static);
  EXPECT_EQ(models.back().fingers(1).friction_cone_mu(), 0.0) << "no contact, no cone";
  EXPECT_EQ(codec::ToEigen(models.back().fingers(1).f0_w_n()), V::Zero()) << "the index finger touches nothing";
  EXPECT_TRUE(thumb.contact_state() == v1::CONTACT_STATE_IV || thumb.contact_state() == v1::CONTACT_STATE_V)
      << v1::ContactState_Name(thumb.contact_state());
  const auto traces = out.Of<v1::TouchTrace>(kTactile);
  ASSERT_EQ(traces.size(), 30u);
  EXPECT_TRUE(traces.back().fingers(0).in_contact());
  const v1::FingerTouch& touch = traces.back().fingers(0);
  EXPECT_GT(touch.normal_force_n(), 0.005);
  // the device's force split about the contact normal, and the load the friction law held
  const double f0_N = codec::ToEigen(thumb.f0_w_n()).norm();
  EXPECT_NEAR(std::hypot(touch.normal_force_n(), touch.tangential_force_n()), f0_N, 1e-9 * f0_N);
  EXPECT_GT(touch.friction_normal_force_n(), 0.0);
  EXPECT_LE(touch.friction_tangential_force_n(), scene::ContactOptionsFromScene(scene_).finger_fabric.mu_static *
                                                     touch.friction_normal_force_n() * (1 + 1e-9));
  EXPECT_EQ(traces.back().fingers(1).friction_normal_force_n(), 0.0) << "the index finger touches nothing";
  // one PatchResult per global step (10 ticks at 1 kHz), for the newest patch's step
  const auto results = out.Of<v1::PatchResult>(kGlobal);
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(results[0].patch_id(), 1u);
  EXPECT_EQ(results[0].global_step(), 7u);
  EXPECT_EQ(results[0].local_ticks(), 10u);
  EXPECT_GT(results[0].particle_ids_size(), 0);
  EXPECT_EQ(results[0].position_w_m_size(), 3 * results[0].particle_ids_size());
  EXPECT_EQ(Counter("patch_results_sent"), 3u);
  EXPECT_EQ(Counter("force_models_sent"), 31u);
  EXPECT_GT(Counter("state_IV_ticks") + Counter("state_V_ticks"), 0u);

  // The device lost: no fingers, no force. Zero force on the way out.
  out.Clear();
  loop_.Read(haptex::testing::WrapEnvelope(Thumb(0.002, 99, false), 99), 0.032);
  loop_.Update(0.032, 0.001);
  loop_.Write(out);
  EXPECT_EQ(codec::ToEigen(out.Of<v1::ForceModel>(kBridge).back().fingers(0).f0_w_n()), V::Zero());
  Tick(100, 0.002, out);
  out.Clear();
  loop_.WriteZeroForce(out);
  const auto last = out.Of<v1::ForceModel>(kBridge);
  ASSERT_EQ(last.size(), 1u);
  for (const auto& f : last[0].fingers()) {
    EXPECT_EQ(codec::ToEigen(f.f0_w_n()), V::Zero());
    for (double k : f.stiffness_w_n_per_m()) EXPECT_EQ(k, 0.0);
  }
}

// Without a tactile service each tick's TouchTrace is recorded and sent to nobody: the run's
// F_T/F_N figure needs its normal force.
TEST_F(LocalContactLoopTest, WithoutTactileTheTouchTraceIsRecordedNotSent) {
  runtime::HealthReporter health("local_contact");
  LocalContactLoop alone(LocalContactConfig{1000.0, {true, true}, 0.010},
                         {kBridge, kGlobal, std::nullopt, std::nullopt}, &builder_, &health);
  haptex::testing::CapturedOutbox out;
  alone.Read(haptex::testing::WrapEnvelope(Patch(1, 7), 1000), 0.0);
  EXPECT_TRUE(builder_.RunOnce());
  for (int k = 1; k <= 5; ++k) {
    alone.Read(
        haptex::testing::WrapEnvelope(Thumb(0.002, static_cast<std::uint64_t>(k)), static_cast<std::uint64_t>(k)),
        k * 0.001);
    alone.Update(k * 0.001, 0.001);
    alone.Write(out);
  }
  EXPECT_EQ(out.Recorded<v1::TouchTrace>(), 5u);
  EXPECT_EQ(out.Count<v1::TouchTrace>(), 0u);
  EXPECT_EQ(out.Count<v1::ForceModel>(), 5u);
}

// The viewer gets a copy every 1/30 s holding each finger's strongest force since the last copy:
// a press shorter than that period (here 3 ms of 60) still shows, at its full size.
TEST_F(LocalContactLoopTest, TheViewersCopyHoldsEachFingersPeakSinceTheLast) {
  constexpr services::PeerId kViewer = 3;
  runtime::HealthReporter health("local_contact");
  LocalContactConfig config{1000.0, {true, true}, 0.010};
  config.viewer_hz = 50.0;  // every 20 ticks
  LocalContactLoop watched(config, {kBridge, kGlobal, kTactile, kViewer}, &builder_, &health);
  haptex::testing::CapturedOutbox out;
  watched.Read(haptex::testing::WrapEnvelope(Patch(1, 7), 1000), 0.0);
  EXPECT_TRUE(builder_.RunOnce());
  std::vector<double> bridge_n;
  std::vector<v1::FingerForceModel> bridge_thumb;
  for (int k = 1; k <= 60; ++k) {
    const double depth_m = (k >= 35 && k < 38) ? 0.004 : 0.001;  // a short hard press in the second period
    watched.Read(
        haptex::testing::WrapEnvelope(Thumb(depth_m, static_cast<std::uint64_t>(k)), static_cast<std::uint64_t>(k)),
        k * 0.001);
    watched.Update(k * 0.001, 0.001);
    watched.Write(out);
    bridge_thumb.push_back(out.Of<v1::ForceModel>(kBridge).back().fingers(0));
    bridge_n.push_back(codec::ToEigen(bridge_thumb.back().f0_w_n()).norm());
  }
  const auto copies = out.Of<v1::ForceModel>(kViewer);
  ASSERT_EQ(copies.size(), 3u) << "at ticks 1, 21 and 41";
  // each copy: the largest of the ticks since the one before (the first: tick 1 alone)
  const std::array<std::pair<int, int>, 3> windows{{{1, 1}, {2, 21}, {22, 41}}};
  for (std::size_t c = 0; c < copies.size(); ++c) {
    std::size_t strongest = static_cast<std::size_t>(windows[c].first - 1);
    for (int k = windows[c].first; k <= windows[c].second; ++k)
      if (bridge_n[static_cast<std::size_t>(k - 1)] > bridge_n[strongest]) strongest = static_cast<std::size_t>(k - 1);
    // the whole entry of that tick: its force, stiffness, pose and state together
    EXPECT_EQ(copies[c].fingers(0).SerializeAsString(), bridge_thumb[strongest].SerializeAsString()) << "copy " << c;
    EXPECT_EQ(copies[c].fingers(1).finger(), v1::FINGER_INDEX);
  }
  const double held_n = codec::ToEigen(copies[2].fingers(0).f0_w_n()).norm();
  EXPECT_GT(held_n, 1.5 * bridge_n[40]) << "the press (ticks 35-37) shows, though it was over by tick 41";
  EXPECT_EQ(copies[2].based_on_controller_sequence(), 41u) << "the newest tick's sequence";
}

TEST_F(LocalContactLoopTest, OlderFingerStatesAndBadPatchesAreRefusedAndCounted) {
  haptex::testing::CapturedOutbox out;
  loop_.Read(haptex::testing::WrapEnvelope(Thumb(0.002, 50), 50), 0.0);
  loop_.Read(haptex::testing::WrapEnvelope(Thumb(0.002, 40), 40), 0.0);  // reordered: older
  loop_.Update(0.0, 0.001);
  loop_.Write(out);
  EXPECT_EQ(out.Of<v1::ForceModel>(kBridge).back().based_on_controller_sequence(), 50u);

  v1::LocalPatch bad = Patch(2, 1);
  bad.mutable_position_w_m()->RemoveLast();  // arrays that do not match
  loop_.Read(haptex::testing::WrapEnvelope(bad, 60), 0.0);
  v1::LocalPatch far_ids = Patch(3, 1);
  far_ids.set_particle_ids(0, 1u << 30);  // beyond the fabric's ids
  loop_.Read(haptex::testing::WrapEnvelope(far_ids, 61), 0.0);
  v1::LocalPatch nan = Patch(4, 1);
  nan.set_velocity_w_m_per_s(0, std::nan(""));
  loop_.Read(haptex::testing::WrapEnvelope(nan, 62), 0.0);
  EXPECT_FALSE(builder_.RunOnce()) << "nothing was queued";
  loop_.Write(out);
  EXPECT_EQ(Counter("patches_received"), 3u);
  EXPECT_EQ(Counter("patches_rejected"), 3u);

  // Four good patches before the builder runs: three slots, the fourth is dropped as busy.
  for (int i = 0; i < 4; ++i) loop_.Read(haptex::testing::WrapEnvelope(Patch(10 + i, 2), 70 + i), 0.0);
  loop_.Write(out);
  EXPECT_EQ(Counter("patches_dropped_busy"), 1u);
  while (builder_.RunOnce()) {
  }
  loop_.Update(0.0, 0.001);
  EXPECT_EQ(loop_.counters().patch_handoffs, 3u);
  ASSERT_NE(loop_.patch(), nullptr);
  EXPECT_EQ(loop_.patch()->patch_id, 12u) << "the newest built patch is the one rendered";
}

TEST_F(LocalContactLoopTest, WarmedUpTickDoesNotAllocate) {
  if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting is off in this build";
  runtime::HealthReporter health("local_contact");
  // watched by a viewer: its peak-holding copy too must not allocate
  LocalContactLoop watched(LocalContactConfig{1000.0, {true, true}, 0.010}, {kBridge, kGlobal, kTactile, 3}, &builder_,
                           &health);
  haptex::testing::CapturedOutbox out;
  out.capture = false;
  watched.Read(haptex::testing::WrapEnvelope(Patch(1, 1), 1), 0.0);
  builder_.RunOnce();
  for (int k = 1; k <= 200; ++k) {  // warm-up: the patch swapped in, the pinch of contact formed
    watched.Read(
        haptex::testing::WrapEnvelope(Thumb(0.002, static_cast<std::uint64_t>(k)), static_cast<std::uint64_t>(k)),
        k * 0.001);
    watched.Update(k * 0.001, 0.001);
    watched.Write(out);
  }
  // the envelopes are made before counting: a received envelope lives on the messenger's arena
  std::vector<v1::Envelope> states;
  for (int k = 201; k <= 300; ++k)
    states.push_back(haptex::testing::WrapEnvelope(Thumb(0.002, k), static_cast<std::uint64_t>(k)));
  haptex::testing::AllocationCounter counter;
  for (int k = 201; k <= 300; ++k) {
    watched.Read(states[static_cast<std::size_t>(k - 201)], k * 0.001);
    watched.Update(k * 0.001, 0.001);
    watched.Write(out);
  }
  EXPECT_EQ(counter.count(), 0);
  EXPECT_EQ(out.Count<v1::ForceModel>(), 300u + 10u) << "to the bridge every tick, to the viewer every 33rd";
  EXPECT_GE(out.Count<v1::PatchResult>(), 29u);
}

}  // namespace
}  // namespace haptex::local_contact
