#include "services/local_contact/local_contact_loop.h"

#include <algorithm>
#include <cmath>

#include "libs/codec/message_conversion.h"
#include "services/local_contact/local_contact_codec.h"

namespace haptex::local_contact {
namespace {

// Field by field: CopyFrom would clear `to` first, which frees its Vec3s (off an arena) only to
// allocate them again.
void CopyInPlace(const v1::FingerForceModel& from, v1::FingerForceModel* to) {
  to->set_finger(from.finger());
  *to->mutable_f0_w_n() = from.f0_w_n();
  *to->mutable_x0_w_m() = from.x0_w_m();
  *to->mutable_stiffness_w_n_per_m() = from.stiffness_w_n_per_m();
  *to->mutable_cross_stiffness_w_n_per_m() = from.cross_stiffness_w_n_per_m();
  *to->mutable_friction_cone_axis_w() = from.friction_cone_axis_w();
  to->set_friction_cone_mu(from.friction_cone_mu());
  to->set_ttl_s(from.ttl_s());
  to->set_contact_state(from.contact_state());
}

}  // namespace

LocalContactLoop::LocalContactLoop(const LocalContactConfig& config, const LocalContactPeers& peers,
                                   PatchBuilder* builder, runtime::HealthReporter* health)
    : config_(config),
      peers_(peers),
      builder_(builder),
      health_(health),
      viewer_every_ticks_(std::max<std::int64_t>(1, std::llround(config.rate_hz / config.viewer_hz))) {
  ids_.models = health_->AddCounter("force_models_sent");
  ids_.patches = health_->AddCounter("patches_received");
  ids_.busy = health_->AddCounter("patches_dropped_busy");
  ids_.rejected = health_->AddCounter("patches_rejected");
  ids_.handoffs = health_->AddCounter("patch_handoffs");
  ids_.results = health_->AddCounter("patch_results_sent");
  ids_.stale_states = health_->AddCounter("stale_finger_states_ticks");
  static constexpr std::array<const char*, 9> kStateNames = {"state_I_ticks",   "state_II_ticks",   "state_III_ticks",
                                                             "state_IV_ticks",  "state_V_ticks",    "state_VI_ticks",
                                                             "state_VII_ticks", "state_VIII_ticks", "state_IX_ticks"};
  for (std::size_t i = 0; i < kStateNames.size(); ++i) ids_.states[i] = health_->AddCounter(kStateNames[i]);
  // the messages' repeated fields sized once, before the loop
  FillForceModel(nullptr, fingers_, 0, config_.force_model_ttl_s, &force_model_);
  viewer_force_model_ = force_model_;
  touch_.add_fingers();
  touch_.add_fingers();
}

void LocalContactLoop::Read(const v1::Envelope& envelope, double t_s) {
  switch (envelope.body_case()) {
    case v1::Envelope::kFingerStates:
      if (!newest_states_.Accept(envelope)) return;
      finger_states_rx_s_ = t_s;
      controller_sequence_ = envelope.finger_states().controller_sequence();
      // a finger without contact is met where it will be when the answer arrives; one in contact
      // where it is when the bridge applies the force (the model's stiffness carries the rest)
      ahead_ = {!in_contact_[0], !in_contact_[1]};
      fingers_ = FingerInputs(envelope.finger_states(), config_.scene_fingers, ahead_, &at_bridge_W_m_);
      return;
    case v1::Envelope::kLocalPatch:
      ++counters_.patches_received;
      switch (builder_->Submit(envelope.local_patch())) {
        case PatchBuilder::Submitted::kQueued:
          global_step_ = envelope.local_patch().global_step();
          return;
        case PatchBuilder::Submitted::kBusy:
          ++counters_.patches_dropped_busy;
          return;
        case PatchBuilder::Submitted::kRejected:
          ++counters_.patches_rejected;
          return;
      }
      return;
    default:
      return;
  }
}

void LocalContactLoop::Update(double t_s, double /*dt_s*/) {
  fingers_known_ = finger_states_rx_s_ >= 0.0 && t_s - finger_states_rx_s_ <= config_.finger_states_stale_s;
  if (finger_states_rx_s_ >= 0.0 && !fingers_known_) ++counters_.stale_finger_states_ticks;
  // Swap in what the builder finished (the newest last), carrying the local state across.
  while (std::unique_ptr<dual_layer::LocalPatch> fresh = builder_->TakeBuilt()) {
    if (patch_) {
      dual_layer::HandOff(*patch_, fresh.get());
      builder_->Dispose(std::move(patch_));
    }
    patch_ = std::move(fresh);
    ++counters_.patch_handoffs;
  }
  // Contact and one patch step at the fingers' newest poses; zero force while there is no fabric.
  contact_ = nullptr;
  if (patch_) {
    contact_ = &patch_->Tick(fingers_[0], fingers_[1]);
    ++counters_.state_ticks[static_cast<std::size_t>(static_cast<int>(contact_->state) - 1)];
  }
  // In contact: the force at the bridge's pose still pushes. A finger met ahead stays ahead until
  // its model, extrapolated back to where the bridge has it now, pushes too: switching as soon as
  // the ahead pose touched would bounce between a touching and a not yet touching pose.
  for (std::size_t f = 0; f < 2; ++f) {
    in_contact_[f] = false;
    if (contact_ == nullptr || !fingers_[f].present) continue;
    const contact::FingerContactOutput& o = contact_->finger[f];
    const Eigen::Vector3d at_bridge_N =
        o.force_W_N + o.stiffness_W_N_per_m * (at_bridge_W_m_[f] - fingers_[f].pose.p_W_m) +
        o.cross_stiffness_W_N_per_m * (at_bridge_W_m_[1 - f] - fingers_[1 - f].pose.p_W_m);
    in_contact_[f] = ahead_[f] ? at_bridge_N.dot(o.force_W_N) > 0.0 : !o.force_W_N.isZero(0.0);
  }
  result_due_ = patch_ && peers_.global_sim && patch_->ResultDue(1.0 / config_.rate_hz);
}

void LocalContactLoop::Write(services::Outbox& out) {
  if (fingers_known_) {
    FillForceModel(contact_, fingers_, controller_sequence_, config_.force_model_ttl_s, &force_model_);
    if (out.Send(peers_.bridge, force_model_)) ++counters_.force_models_sent;
    if (peers_.viewer) HoldPeakForViewer();
  }
  const bool to_viewer = peers_.viewer && --ticks_to_viewer_ <= 0;
  if (to_viewer) ticks_to_viewer_ = viewer_every_ticks_;
  if (contact_ != nullptr) {
    FillTouchTrace(*contact_, patch_->sim->state().time_s, &touch_);
    // without a tactile display the run still keeps each tick's normal force: the run folder's
    // F_T/F_N figure (paper Fig. 9) is drawn from it
    if (peers_.tactile) {
      out.Send(*peers_.tactile, touch_);
    } else {
      out.Record(touch_);
    }
    if (to_viewer) out.Send(*peers_.viewer, touch_);
  }
  if (to_viewer && viewer_force_held_) {
    out.Send(*peers_.viewer, viewer_force_model_);
    viewer_force_held_ = false;
  }
  if (result_due_) {
    dual_layer::FillPatchResult(global_step_, patch_.get(), &result_);
    ToMessage(result_, &result_message_);
    if (out.Send(*peers_.global_sim, result_message_)) ++counters_.patch_results_sent;
  }
  PublishCounters();
}

void LocalContactLoop::HoldPeakForViewer() {
  for (int f = 0; f < force_model_.fingers_size(); ++f) {
    const v1::FingerForceModel& now = force_model_.fingers(f);
    const double magnitude = codec::ToEigen(now.f0_w_n()).norm();
    double& held_n = viewer_peak_n_[static_cast<std::size_t>(f)];
    if (viewer_force_held_ && magnitude <= held_n) continue;
    CopyInPlace(now, viewer_force_model_.mutable_fingers(f));
    held_n = magnitude;
  }
  viewer_force_model_.set_based_on_controller_sequence(force_model_.based_on_controller_sequence());
  viewer_force_held_ = true;
}

void LocalContactLoop::WriteZeroForce(services::Outbox& out) {
  ZeroForceModel(&force_model_);
  out.Send(peers_.bridge, force_model_);
}

void LocalContactLoop::PublishCounters() {
  health_->SetCounter(ids_.models, counters_.force_models_sent);
  health_->SetCounter(ids_.patches, counters_.patches_received);
  health_->SetCounter(ids_.busy, counters_.patches_dropped_busy);
  health_->SetCounter(ids_.rejected, counters_.patches_rejected + builder_->build_failures());
  health_->SetCounter(ids_.handoffs, counters_.patch_handoffs);
  health_->SetCounter(ids_.results, counters_.patch_results_sent);
  health_->SetCounter(ids_.stale_states, counters_.stale_finger_states_ticks);
  for (std::size_t i = 0; i < counters_.state_ticks.size(); ++i)
    health_->SetCounter(ids_.states[i], counters_.state_ticks[i]);
}

}  // namespace haptex::local_contact
