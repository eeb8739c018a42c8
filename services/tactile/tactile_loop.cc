#include "services/tactile/tactile_loop.h"

#include "libs/codec/message_conversion.h"

namespace haptex::tactile_service {

TactileLoop::TactileLoop(std::unique_ptr<tactile::RendererModel> model, double stale_after_s,
                         std::optional<services::PeerId> display, runtime::HealthReporter* health)
    : model_(std::move(model)), stale_after_s_(stale_after_s), display_(display), health_(health) {
  if (health_ == nullptr) return;
  ids_.frames = health_->AddCounter("pin_frames_sent");
  ids_.traces = health_->AddCounter("touch_traces");
  ids_.bad = health_->AddCounter("bad_input");
}

void TactileLoop::Read(const v1::Envelope& envelope, double t_s) {
  if (envelope.body_case() != v1::Envelope::kTouchTrace) return;
  OnTouchTrace(envelope.touch_trace(), t_s);
  ++touch_traces_;
}

void TactileLoop::OnTouchTrace(const v1::TouchTrace& trace, double now_s) {
  for (const v1::FingerTouch& touch : trace.fingers()) {
    const int i = codec::FingerSlot(touch.finger());
    if (i < 0) {
      ++bad_fingers_;
      continue;
    }
    tactile::FingerInput& in = inputs_[static_cast<std::size_t>(i)];
    in.in_contact = touch.in_contact();
    in.touch_point_m = {touch.u_m(), touch.v_m()};
    in.slip_velocity_m_per_s = {touch.slip_u_m_per_s(), touch.slip_v_m_per_s()};
    in.normal_force_N = touch.normal_force_n();
    in.orientation_rad = touch.finger_angle_rad();
    in.contact_radius_m = 0.0;  // derived from the normal force
    input_time_s_[static_cast<std::size_t>(i)] = now_s;
  }
}

void TactileLoop::Update(double t_s, double dt_s) {
  t_s_ = t_s;
  frame_ready_ = Tick(t_s, dt_s, &frame_);
}

void TactileLoop::Write(services::Outbox& out) {
  if (frame_ready_ && display_ && out.Send(*display_, frame_)) ++frames_sent_;
  if (frame_ready_ && viewer_ && t_s_ >= next_view_s_) {
    next_view_s_ = t_s_ + viewer_period_s_;
    out.Send(*viewer_, frame_);
  }
  if (health_ == nullptr) return;
  health_->SetCounter(ids_.frames, frames_sent_);
  health_->SetCounter(ids_.traces, touch_traces_);
  health_->SetCounter(ids_.bad, bad_fingers_ + counters(0).bad_input + counters(1).bad_input);
}

void TactileLoop::WriteSilence(services::Outbox& out) {
  if (frame_.fingers_size() == 0 || !display_) return;
  for (auto& finger : *frame_.mutable_fingers()) {
    for (auto& a : *finger.mutable_amplitude_40hz()) a = 0.0f;
    for (auto& a : *finger.mutable_amplitude_320hz()) a = 0.0f;
  }
  out.Send(*display_, frame_);
}

bool TactileLoop::Tick(double now_s, double dt_s, v1::PinFrame* out) {
  bool completed = false;
  for (std::size_t i = 0; i < 2; ++i) {
    tactile::FingerInput input = inputs_[i];
    // no news from local_contact: the finger is treated as lifted (silence)
    if (now_s - input_time_s_[i] > stale_after_s_) input.in_contact = false;
    completed |= tactile::RenderStep(*model_, input, dt_s, &states_[i], &workspace_) > 0;
  }
  if (!completed) return false;
  while (out->fingers_size() < 2) out->add_fingers();
  out->set_frame_index(++frame_index_);
  for (int i = 0; i < 2; ++i) {
    v1::FingerPins* pins = out->mutable_fingers(i);
    pins->set_finger(codec::FingerOfSlot(i));
    const tactile::PinFrame& frame = states_[static_cast<std::size_t>(i)].frame;
    pins->mutable_amplitude_40hz()->Resize(tactile::PinLayout::kPinCount, 0.0f);
    pins->mutable_amplitude_320hz()->Resize(tactile::PinLayout::kPinCount, 0.0f);
    // PinFrame pin k is row k / 4 (along the finger), column k % 4; the core's index is i + 6 j
    for (int k = 0; k < tactile::PinLayout::kPinCount; ++k) {
      const auto core = static_cast<std::size_t>(tactile::PinLayout::Index(k / 4, k % 4));
      pins->set_amplitude_40hz(k, frame.amplitude_40hz[core]);
      pins->set_amplitude_320hz(k, frame.amplitude_320hz[core]);
    }
  }
  return true;
}

}  // namespace haptex::tactile_service
