// haptex-local-contact: the haptic-rate layer (paper sections 4 and 5). Every tick it takes the
// newest FingerStates, runs the contact models (libs/contact) on the local patch and one step of
// the patch's dynamics, and sends a ForceModel per finger to the device bridge (F0, K, x0: the
// bridge evaluates it at 5 kHz) and a TouchTrace to tactile. Once per global step it returns the
// patch's state and the contact forces to global_sim as a PatchResult.
//
// Patches from global_sim are copied into preallocated storage and built on a helper thread; the
// loop swaps a finished patch in (carrying particles, anchors and friction state across by
// particle id) and hands the old one back to be freed there. It never waits: with no patch yet,
// or global_sim late, it renders from the patch it has.
//
// Receives: FingerStates (bridge), LocalPatch (global_sim), Control.
// Sends: ForceModel to "bridge", TouchTrace to "tactile" (optional), PatchResult to "global_sim",
// Health to the launcher.

#include <spdlog/spdlog.h>

#include <array>
#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

#include "libs/base/clock.h"
#include "libs/runtime/latency_histogram.h"
#include "libs/runtime/periodic_loop.h"
#include "libs/runtime/spsc_ring.h"
#include "libs/scene/cloth_setup.h"
#include "services/common/service_context.h"
#include "services/common/refined_grid.h"
#include "services/local_contact/contact_config.h"
#include "services/local_contact/local_patch_runtime.h"
#include "services/local_contact/patch_data.h"

namespace haptex::local_contact {
namespace {

struct Options {
  double rate_hz = 0;        // 0: the scene's local rate, else 1000
  int max_patch_particles = 4096;
};

constexpr int kSlots = 3;

v1::ContactState ToProto(contact::ContactState s) { return static_cast<v1::ContactState>(static_cast<int>(s)); }

void SetVec(const Eigen::Vector3d& v, v1::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

int Run(services::ServiceContext& context, const Options& options) {
  if (context.scene() == nullptr) throw std::invalid_argument("local_contact needs --scene");
  const scene::LoadedScene& loaded = *context.scene();
  const double rate_hz = options.rate_hz > 0 ? options.rate_hz
                         : loaded.scene.rates().local_hz() > 0 ? loaded.scene.rates().local_hz() : 1000.0;
  const scene::ClothSetup setup = scene::MakeClothSetup(loaded);
  // Patch particle ids: the fabric's, and above them refined particles (model.patch_refinement).
  const services::RefinedGrid refined = services::MakeRefinedGrid(
      setup.grid.particles_warp, setup.grid.particles_weft, static_cast<int>(loaded.scene.model().patch_refinement()));
  const int particle_id_space = static_cast<int>(refined.id_space());
  const contact::ContactOptions contact_options = ContactOptionsFromScene(loaded);
  const textile::StepOptions step = LocalStepOptions(loaded, rate_hz);
  const std::array<bool, 2> scene_fingers = SceneFingers(loaded);
  const auto bridge = context.RequirePeer("bridge");
  const auto global = context.FindPeer("global_sim");
  const auto tactile = context.FindPeer("tactile");

  // Patch hand-over between the loop and the builder thread.
  std::array<std::unique_ptr<PatchData>, kSlots> slots;
  runtime::SpscRing<int, 4> free_slots, pending_slots;
  for (int i = 0; i < kSlots; ++i) {
    slots[static_cast<std::size_t>(i)] = std::make_unique<PatchData>(options.max_patch_particles);
    free_slots.TryPush(i);
  }
  runtime::SpscRing<PatchRuntime*, 4> built, disposal;
  std::atomic<bool> stop_builder{false};
  std::atomic<std::uint64_t> build_failures{0};
  std::thread builder([&] {
    while (!stop_builder.load()) {
      PatchRuntime* old = nullptr;
      while (disposal.TryPop(&old)) delete old;
      int slot = -1;
      if (!pending_slots.TryPop(&slot)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        continue;
      }
      try {
        auto rt = BuildPatch(*slots[static_cast<std::size_t>(slot)], setup.material, setup.model_options,
                             step, contact_options, particle_id_space);
        PatchRuntime* raw = rt.release();
        while (!built.TryPush(raw) && !stop_builder.load()) std::this_thread::sleep_for(std::chrono::microseconds(200));
      } catch (const std::exception&) {
        build_failures.fetch_add(1);
      }
      free_slots.TryPush(slot);
    }
  });

  auto& health = context.health();
  runtime::PeriodicLoop loop("local_contact", rate_hz);
  health.AddLoop(&loop.stats());
  runtime::LatencyHistogram compute;
  health.AddLatency("tick_compute", &compute);
  const auto c_models = health.AddCounter("force_models_sent");
  const auto c_patches = health.AddCounter("patches_received");
  const auto c_patch_busy = health.AddCounter("patches_dropped_busy");
  const auto c_patch_bad = health.AddCounter("patches_rejected");
  const auto c_handoffs = health.AddCounter("patch_handoffs");
  const auto c_results = health.AddCounter("patch_results_sent");
  const auto c_dropped = health.AddCounter("datagrams_dropped");
  std::array<runtime::HealthReporter::CounterId, 9> c_state{};
  static constexpr std::array<const char*, 9> kStateNames = {
      "state_I_ticks", "state_II_ticks", "state_III_ticks", "state_IV_ticks", "state_V_ticks",
      "state_VI_ticks", "state_VII_ticks", "state_VIII_ticks", "state_IX_ticks"};
  for (std::size_t i = 0; i < 9; ++i) c_state[i] = health.AddCounter(kStateNames[i]);
  std::array<std::uint64_t, 9> state_ticks{};
  health.SetState(v1::Health::STATE_READY);

  std::unique_ptr<PatchRuntime> patch;
  std::array<contact::FingerInput, 2> fingers{};
  std::uint64_t controller_sequence = 0, global_step = 0;
  std::uint64_t models = 0, patches = 0, patches_busy = 0, patches_bad = 0, handoffs = 0, results = 0;
  net::NewestWins newest_states;
  v1::ForceModel force_model;
  v1::TouchTrace touch;
  v1::PatchResult result;
  for (int f = 0; f < 2; ++f) {
    force_model.add_fingers()->mutable_stiffness_w_n_per_m()->Resize(9, 0.0);
    touch.add_fingers();
  }
  std::int64_t now_ns = base::SteadyNowNs();

  loop.Run(
      [&](const runtime::TickInfo& tick) {
        now_ns = tick.now_ns;
        context.messenger().Drain([&](const v1::Envelope& e, const net::Messenger::Endpoint&) {
          if (context.HandleControl(e) != services::ServiceContext::ControlResult::kNotControl) return;
          if (e.body_case() == v1::Envelope::kFingerStates) {
            if (!newest_states.Accept(e)) return;
            const v1::FingerStates& s = e.finger_states();
            controller_sequence = s.controller_sequence();
            fingers = {};
            for (const v1::FingerState& f : s.fingers()) {
              const int slot = f.finger() == v1::FINGER_THUMB ? 0 : f.finger() == v1::FINGER_INDEX ? 1 : -1;
              if (slot < 0 || !s.device_ok() || !scene_fingers[static_cast<std::size_t>(slot)]) continue;
              contact::FingerInput& in = fingers[static_cast<std::size_t>(slot)];
              in.present = true;
              // The predicted pose: where the finger is when this force reaches it.
              const v1::Vec3& p = f.has_predicted_position_w_m() ? f.predicted_position_w_m() : f.position_w_m();
              in.pose.p_W_m = {p.x(), p.y(), p.z()};
              const v1::Quat& q = f.orientation_wf();
              Eigen::Quaterniond quat(q.w(), q.x(), q.y(), q.z());
              in.pose.R_WF = quat.norm() > 0.5 ? quat.normalized().toRotationMatrix() : Eigen::Matrix3d::Identity();
            }
          } else if (e.body_case() == v1::Envelope::kLocalPatch) {
            ++patches;
            int slot = -1;
            if (!free_slots.TryPop(&slot)) {
              ++patches_busy;
              return;
            }
            if (slots[static_cast<std::size_t>(slot)]->CopyFrom(e.local_patch(), static_cast<std::uint32_t>(particle_id_space)) !=
                PatchData::Copy::kOk) {
              ++patches_bad;
              free_slots.TryPush(slot);
              return;
            }
            global_step = e.local_patch().global_step();
            pending_slots.TryPush(slot);
          }
        });

        const std::int64_t t0 = base::SteadyNowNs();
        PatchRuntime* ready = nullptr;
        while (built.TryPop(&ready)) {
          std::unique_ptr<PatchRuntime> fresh(ready);
          if (patch) {
            HandOff(*patch, fresh.get());
            disposal.TryPush(patch.release());  // freed on the builder thread
          }
          patch = std::move(fresh);
          ++handoffs;
        }

        // Contact and one patch step; zero force while there is no fabric yet.
        const contact::ContactOutput* out = nullptr;
        if (patch) {
          out = &patch->sim->Tick(fingers[0], fingers[1]);
          patch->force_sum_W_N += patch->sim->solver().particle_force_W_N();
          ++patch->ticks_since_result;
          ++state_ticks[static_cast<std::size_t>(static_cast<int>(out->state) - 1)];
        }
        force_model.set_based_on_controller_sequence(controller_sequence);
        for (int f = 0; f < 2; ++f) {
          v1::FingerForceModel* m = force_model.mutable_fingers(f);
          m->set_finger(f == 0 ? v1::FINGER_THUMB : v1::FINGER_INDEX);
          const contact::FingerInput& in = fingers[static_cast<std::size_t>(f)];
          Eigen::Vector3d force = Eigen::Vector3d::Zero();
          Eigen::Matrix3d k = Eigen::Matrix3d::Zero();
          if (out != nullptr && in.present) {
            force = out->finger[static_cast<std::size_t>(f)].force_W_N;
            k = out->finger[static_cast<std::size_t>(f)].stiffness_W_N_per_m;
          }
          SetVec(force, m->mutable_f0_w_n());
          SetVec(in.pose.p_W_m, m->mutable_x0_w_m());
          for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) m->set_stiffness_w_n_per_m(3 * r + c, k(r, c));
          }
          m->set_ttl_s(0.010);
          m->set_contact_state(out != nullptr ? ToProto(out->state) : v1::CONTACT_STATE_I);
        }
        if (context.Send(bridge, force_model)) ++models;

        if (out != nullptr && tactile) {
          touch.set_sim_time_s(patch->sim->state().time_s);
          for (int f = 0; f < 2; ++f) {
            const contact::FingerContactOutput& o = out->finger[static_cast<std::size_t>(f)];
            v1::FingerTouch* t = touch.mutable_fingers(f);
            t->set_finger(f == 0 ? v1::FINGER_THUMB : v1::FINGER_INDEX);
            t->set_in_contact(o.touching);
            t->set_u_m(o.touch_uv_m.x());
            t->set_v_m(o.touch_uv_m.y());
            t->set_slip_u_m_per_s(o.slip_uv_m_per_s.x());
            t->set_slip_v_m_per_s(o.slip_uv_m_per_s.y());
            t->set_normal_force_n(o.normal_force_N);
            t->set_finger_angle_rad(o.finger_angle_rad);
            t->set_contact_state(ToProto(out->state));
          }
          context.Send(*tactile, touch);
        }

        if (patch && global &&
            patch->ticks_since_result * (1.0 / rate_hz) >= patch->global_dt_s - 0.5 / rate_hz) {
          FillPatchResult(global_step, patch.get(), &result);
          if (context.Send(*global, result)) ++results;
        }
        compute.Record(base::SteadyNowNs() - t0);

        health.SetCounter(c_models, models);
        health.SetCounter(c_patches, patches);
        health.SetCounter(c_patch_busy, patches_busy);
        health.SetCounter(c_patch_bad, patches_bad + build_failures.load());
        health.SetCounter(c_handoffs, handoffs);
        health.SetCounter(c_results, results);
        health.SetCounter(c_dropped, context.messenger().received().TotalDropped());
        for (std::size_t i = 0; i < 9; ++i) health.SetCounter(c_state[i], state_ticks[i]);
        context.Tick(tick.now_ns);
      },
      [&] { return context.StopRequested(now_ns); });

  // Zero force before leaving (the bridge's watchdog would ramp down anyway).
  for (int f = 0; f < force_model.fingers_size(); ++f) {
    SetVec(Eigen::Vector3d::Zero(), force_model.mutable_fingers(f)->mutable_f0_w_n());
    for (int k = 0; k < 9; ++k) force_model.mutable_fingers(f)->set_stiffness_w_n_per_m(k, 0.0);
  }
  context.Send(bridge, force_model);
  stop_builder.store(true);
  builder.join();
  PatchRuntime* left = nullptr;
  while (built.TryPop(&left)) delete left;
  while (disposal.TryPop(&left)) delete left;
  context.log().info("local_contact: {} force models, {} patches ({} handed off, {} busy, {} rejected), "
                     "{} results, overruns {}, tick compute p50 {:.1f} us p99 {:.1f} us",
                     models, patches, handoffs, patches_busy, patches_bad + build_failures.load(), results,
                     loop.stats().overruns, compute.Percentile(0.5) * 1e-3, compute.Percentile(0.99) * 1e-3);
  return 0;
}

}  // namespace
}  // namespace haptex::local_contact

int main(int argc, char** argv) {
  auto options = std::make_shared<haptex::local_contact::Options>();
  return haptex::services::RunService(
      argc, argv, "local_contact", "haptic-rate contact on the local patch; ForceModel to the bridge",
      [options](CLI::App& app) {
        app.add_option("--rate", options->rate_hz, "local rate [Hz] (default: the scene's, else 1000)")
            ->check(CLI::Range(100.0, 10000.0));
        app.add_option("--max-patch-particles", options->max_patch_particles,
                       "largest patch accepted from global_sim")
            ->check(CLI::Range(16, 65536));
      },
      [options](haptex::services::ServiceContext& context) { return haptex::local_contact::Run(context, *options); });
}
