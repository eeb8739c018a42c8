#include "services/global_sim/global_sim_loop.h"

#include <cmath>

#include "libs/scene/scene_contact.h"
#include "libs/scene/scene_defaults.h"
#include "services/global_sim/global_sim_codec.h"

namespace haptex::global_sim {
namespace {

scene::ClothSetup SetupAt(const scene::LoadedScene& scene, double rate_hz) {
  scene::ClothSetup setup = scene::MakeClothSetup(scene);
  setup.step_options.dt_s = 1.0 / rate_hz;
  return setup;
}

}  // namespace

GlobalSimLoop::GlobalSimLoop(const scene::LoadedScene& scene, double rate_hz, const GlobalSimPeers& peers,
                             runtime::HealthReporter* health)
    : setup_(SetupAt(scene, rate_hz)),
      cloth_(scene::MakeClothInstance(setup_)),
      stepper_(cloth_.model, setup_.step_options),
      loads_(scene.scene, cloth_.model),
      peers_(peers),
      health_(health),
      // a finger touches the fabric's surface, half its thickness off the simulated mid-surface
      finger_reach_m_(scene::FingerReachM(scene.scene) + scene::ContactOptionsFromScene(scene).fabric_half_thickness_m),
      margin_m_(scene::PatchMarginM(scene.scene)),
      frame_period_s_(1.0 / scene::ClothFrameHz(scene.scene)),
      record_cloth_frames_(scene.scene.recording().cloth_frames()),
      refined_(dual_layer::MakeRefinedGrid(cloth_.model.mesh.particles_warp(), cloth_.model.mesh.particles_weft(),
                                           static_cast<int>(scene.scene.model().patch_refinement()))),
      merged_(static_cast<int>(std::ceil(dual_layer::kLastResultHoldMax_s / setup_.step_options.dt_s - 1e-9)),
              cloth_.model.num_particles),
      patch_(static_cast<int>(refined_.id_space())),
      result_(static_cast<int>(refined_.id_space())) {
  ids_.patches = health_->AddCounter("patches_sent");
  // a patch that does not fit one datagram (two fingers far apart, fast motion, refinement) is
  // not sent; local_contact keeps the one it has
  ids_.unsent = health_->AddCounter("patches_not_sent");
  ids_.results = health_->AddCounter("patch_results_merged");
  ids_.results_bad = health_->AddCounter("patch_results_rejected");
  ids_.held_again = health_->AddCounter("patch_results_held_again");
  ids_.nan = health_->AddCounter("fabric_nan_events");
  ids_.cg = health_->AddCounter("cg_not_converged");
  ids_.newton = health_->AddCounter("newton_not_converged");
  ids_.halvings = health_->AddCounter("step_halvings");
}

void GlobalSimLoop::Read(const v1::Envelope& envelope, double /*t_s*/) {
  switch (envelope.body_case()) {
    case v1::Envelope::kFingerStates:
      if (!newest_states_.Accept(envelope)) return;
      spheres_ = FingerSpheres(envelope.finger_states(), finger_reach_m_, setup_.step_options.dt_s, margin_m_);
      return;
    case v1::Envelope::kPatchResult: {
      if (!CopyResult(envelope.patch_result(), &result_)) {
        ++counters_.results_rejected;
        return;
      }
      const int rejected = merged_.Merge(result_, static_cast<int>(refined_.id_space()), &cloth_.state);
      if (rejected < 0) {
        ++counters_.results_rejected;
        return;
      }
      counters_.results_rejected += static_cast<std::uint64_t>(rejected);
      ++counters_.results_merged;
      link_delay_.OnResultMerged(counters_.steps, result_.global_step);
      return;
    }
    default:
      return;
  }
}

void GlobalSimLoop::Update(double t_s, double /*dt_s*/) {
  t_s_ = t_s;
  loads_.Apply(cloth_.state.time_s, &cloth_.state);
  merged_.HoldBeforeStep(&cloth_.state);
  stepper_.Step(&cloth_.state);
  merged_.ReleaseAfterStep(&cloth_.state);
  const Eigen::VectorXd& cut_v = cut_velocity_.Update(cloth_.state.v_W_m_per_s);
  ++counters_.steps;
  patch_ready_ = false;
  patch_rect_ = {};
  if (!peers_.local_contact) return;
  const dual_layer::PatchRect rect = dual_layer::FindPatchRect(cloth_.model, cloth_.state, spheres_);
  if (rect.empty()) return;
  patch_rect_ = rect;
  dual_layer::CutPatch(cloth_.model, cloth_.state, cut_v, rect, ++patch_id_, counters_.steps, setup_.step_options.dt_s,
                       refined_, &patch_);
  patch_.link_round_trip_steps = link_delay_.round_trip_steps();
  patch_ready_ = true;
}

void GlobalSimLoop::Write(services::Outbox& out) {
  if (patch_ready_) {
    ToMessage(patch_, &patch_message_);
    if (out.Send(*peers_.local_contact, patch_message_)) {
      ++counters_.patches_sent;
    } else {
      ++counters_.patches_not_sent;
    }
  }
  // the cloth is recorded when someone watches it or the scene asks: a replay shows it then
  if ((peers_.viewer || record_cloth_frames_) && t_s_ >= next_frame_s_) {
    next_frame_s_ = t_s_ + frame_period_s_;
    for (int c = 0; c < ClothFrameChunks(cloth_.model.num_particles); ++c) {
      FillClothFrame(cloth_.model, cloth_.state, patch_rect_, counters_.cloth_frames, c, &frame_);
      out.Record(frame_);
      if (peers_.viewer) out.Send(*peers_.viewer, frame_);
    }
    ++counters_.cloth_frames;
  }
  PublishCounters();
}

void GlobalSimLoop::PublishCounters() {
  health_->SetCounter(ids_.patches, counters_.patches_sent);
  health_->SetCounter(ids_.unsent, counters_.patches_not_sent);
  health_->SetCounter(ids_.results, counters_.results_merged);
  health_->SetCounter(ids_.results_bad, counters_.results_rejected);
  health_->SetCounter(ids_.held_again, merged_.steps_held_again());
  const textile::FabricDiagnostics& d = cloth_.state.diagnostics;
  health_->SetCounter(ids_.nan, static_cast<std::uint64_t>(d.nan_events));
  health_->SetCounter(ids_.cg, static_cast<std::uint64_t>(d.cg_not_converged));
  health_->SetCounter(ids_.newton, static_cast<std::uint64_t>(d.newton_not_converged));
  health_->SetCounter(ids_.halvings, static_cast<std::uint64_t>(d.step_halvings));
}

}  // namespace haptex::global_sim
