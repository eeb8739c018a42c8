// haptex-global-sim: the whole fabric (libs/textile) at the scene's global rate, hanging from its
// stand (paper section 4, the low-rate layer). From the fingers' states it cuts the local patch
// each finger may touch over the next step and sends it to local_contact; it merges each
// PatchResult (the patch's new shape) back before stepping, holding that part through the step
// (patch_merge.h).
// With model.patch_refinement, the patch it sends is finer than the fabric (services/common/
// refined_grid.h); only the fabric's own particles come back from it.
//
// Receives: FingerStates (device_bridge), PatchResult (local_contact), Control.
// Sends: LocalPatch to local_contact, ClothFrame to the optional "viewer" peer, Health.

#include <spdlog/spdlog.h>

#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "libs/base/clock.h"
#include "libs/runtime/periodic_loop.h"
#include "libs/scene/cloth_setup.h"
#include "libs/scene/scene_defaults.h"
#include "libs/textile/fabric_stepper.h"
#include "services/common/service_context.h"
#include "services/global_sim/patch_cutter.h"
#include "services/global_sim/patch_merge.h"

namespace haptex::global_sim {
namespace {

struct Options {
  double rate_hz = 0;  // 0: the scene's global rate
};

double Or(double v, double fallback) { return v > 0 ? v : fallback; }

Eigen::Vector3d ToEigen(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

int Run(services::ServiceContext& context, const Options& options) {
  if (context.scene() == nullptr) throw std::invalid_argument("global_sim needs --scene");
  const scene::LoadedScene& loaded = *context.scene();
  const v1::Scene& sc = loaded.scene;
  const double rate_hz = Or(options.rate_hz, Or(sc.rates().global_hz(), 100.0));
  scene::ClothSetup setup = scene::MakeClothSetup(loaded);
  setup.step_options.dt_s = 1.0 / rate_hz;
  scene::ClothInstance cloth = scene::MakeClothInstance(setup);
  textile::FabricStepper stepper(cloth.model, setup.step_options);
  const scene::SceneLoads loads(sc, cloth.model);
  const auto local = context.FindPeer("local_contact");
  const auto viewer = context.FindPeer("viewer");

  // Finger reach for the bounding spheres.
  const double reach_m = scene::FingerReachM(sc) + 0.5 * std::max(0.0006, loaded.fabric.thickness_mm() * 1e-3);
  const double margin_m = scene::PatchMarginM(sc);
  const services::RefinedGrid refined = services::MakeRefinedGrid(
      cloth.model.mesh.particles_warp(), cloth.model.mesh.particles_weft(), static_cast<int>(sc.model().patch_refinement()));
  const double frame_hz = std::min(60.0, Or(sc.rates().cloth_frame_hz(), 30.0));

  auto& health = context.health();
  runtime::PeriodicLoop loop("global_sim", rate_hz);
  health.AddLoop(&loop.stats());
  const auto c_patches = health.AddCounter("patches_sent");
  // a patch that does not fit one datagram (two fingers far apart, fast motion, refinement) is
  // not sent; local_contact keeps the one it has
  const auto c_patches_unsent = health.AddCounter("patches_not_sent");
  const auto c_results = health.AddCounter("patch_results_merged");
  const auto c_results_bad = health.AddCounter("patch_results_rejected");
  const auto c_nan = health.AddCounter("fabric_nan_events");
  const auto c_cg = health.AddCounter("cg_not_converged");
  const auto c_dropped = health.AddCounter("datagrams_dropped");
  health.SetState(v1::Health::STATE_READY);

  const int n = cloth.model.num_particles;
  std::vector<int> merged;  // patch interior held through the next step
  TwoStepVelocity cut_velocity;  // sent with the patch
  merged.reserve(static_cast<std::size_t>(n));
  std::array<FingerSphere, 2> spheres{};
  net::NewestWins newest_states;
  v1::LocalPatch patch;
  v1::ClothFrame frame;
  std::uint64_t patch_id = 0, step = 0, patches = 0, patches_unsent = 0, results = 0, results_bad = 0, frames = 0;
  std::int64_t next_frame_ns = 0;
  std::int64_t now_ns = base::SteadyNowNs();
  const double dt = setup.step_options.dt_s;

  loop.Run(
      [&](const runtime::TickInfo& tick) {
        now_ns = tick.now_ns;
        context.messenger().Drain([&](const v1::Envelope& e, const net::Messenger::Endpoint&) {
          if (context.HandleControl(e) != services::ServiceContext::ControlResult::kNotControl) return;
          if (e.body_case() == v1::Envelope::kFingerStates) {
            if (!newest_states.Accept(e)) return;
            spheres = {};
            for (const v1::FingerState& f : e.finger_states().fingers()) {
              const int slot = f.finger() == v1::FINGER_THUMB ? 0 : f.finger() == v1::FINGER_INDEX ? 1 : -1;
              if (slot < 0 || !e.finger_states().device_ok()) continue;
              spheres[static_cast<std::size_t>(slot)] =
                  SweptSphere(ToEigen(f.position_w_m()), ToEigen(f.predicted_position_w_m()),
                              ToEigen(f.velocity_w_m_per_s()), reach_m, dt, margin_m);
            }
          } else if (e.body_case() == v1::Envelope::kPatchResult) {
            const int rejected = MergePatchResult(e.patch_result(), static_cast<int>(refined.id_space()), &cloth.state,
                                                  &merged);
            if (rejected < 0) {
              ++results_bad;
              return;
            }
            results_bad += static_cast<std::uint64_t>(rejected);
            ++results;
          }
        });

        loads.Apply(cloth.state.time_s, &cloth.state);
        stepper.Step(&cloth.state);
        ReleaseMerged(&cloth.state, &merged);
        const Eigen::VectorXd& cut_v = cut_velocity.Update(cloth.state.v_W_m_per_s);
        ++step;

        if (local) {
          const PatchRect rect = FindPatchRect(cloth.model, cloth.state, spheres);
          if (!rect.empty()) {
            FillLocalPatch(cloth.model, cloth.state, cut_v, rect, ++patch_id, step, dt, refined, &patch);
            if (context.Send(*local, patch)) {
              ++patches;
            } else {
              ++patches_unsent;
            }
          }
        }
        if (viewer && tick.now_ns >= next_frame_ns) {
          next_frame_ns = tick.now_ns + static_cast<std::int64_t>(1e9 / frame_hz);
          constexpr int kChunk = 4000;
          const int chunks = (n + kChunk - 1) / kChunk;
          for (int c = 0; c < chunks; ++c) {
            frame.set_frame_index(frames);
            frame.set_sim_time_s(cloth.state.time_s);
            frame.set_particles_u(static_cast<std::uint32_t>(cloth.model.mesh.particles_warp()));
            frame.set_particles_v(static_cast<std::uint32_t>(cloth.model.mesh.particles_weft()));
            frame.set_first_particle(static_cast<std::uint32_t>(c * kChunk));
            frame.set_chunk_index(static_cast<std::uint32_t>(c));
            frame.set_chunk_count(static_cast<std::uint32_t>(chunks));
            frame.clear_position_w_m();
            for (int p = c * kChunk; p < std::min(n, (c + 1) * kChunk); ++p) {
              for (int k = 0; k < 3; ++k) frame.add_position_w_m(static_cast<float>(cloth.state.x_W_m[3 * p + k]));
            }
            context.Send(*viewer, frame);
          }
          ++frames;
        }
        health.SetCounter(c_patches, patches);
        health.SetCounter(c_patches_unsent, patches_unsent);
        health.SetCounter(c_results, results);
        health.SetCounter(c_results_bad, results_bad);
        health.SetCounter(c_nan, static_cast<std::uint64_t>(cloth.state.diagnostics.nan_events));
        health.SetCounter(c_cg, static_cast<std::uint64_t>(cloth.state.diagnostics.cg_not_converged));
        health.SetCounter(c_dropped, context.messenger().received().TotalDropped());
        context.Tick(tick.now_ns);
      },
      [&] { return context.StopRequested(now_ns); });
  context.log().info("global_sim: {} steps, {} patches sent, {} results merged ({} rejected), overruns {}",
                     step, patches, results, results_bad, loop.stats().overruns);
  return 0;
}

}  // namespace
}  // namespace haptex::global_sim

int main(int argc, char** argv) {
  auto options = std::make_shared<haptex::global_sim::Options>();
  return haptex::services::RunService(
      argc, argv, "global_sim", "the whole fabric at the global rate; cuts local patches",
      [options](CLI::App& app) {
        app.add_option("--rate", options->rate_hz, "global rate [Hz] (default: the scene's, else 100)")
            ->check(CLI::Range(1.0, 1000.0));
      },
      [options](haptex::services::ServiceContext& context) { return haptex::global_sim::Run(context, *options); });
}
