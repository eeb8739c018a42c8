#include "services/viewer/viewer_loop.h"

#include "libs/codec/cloth_positions.h"
#include "libs/codec/message_topic.h"

namespace haptex::viewer {

ViewerLoop::ViewerLoop(const ViewerLoopConfig& config, ViewerSink* sink, runtime::HealthReporter* health)
    : config_(config), sink_(sink), health_(health), scene_view_(config.scene) {
  ids_.passed = health_->AddCounter("messages_passed_on");
  ids_.whole = health_->AddCounter("cloth_frames_whole");
  ids_.bad = health_->AddCounter("cloth_chunks_bad");
  ids_.scenes = health_->AddCounter("scene_updates");
  ids_.unknown = health_->AddCounter("messages_without_sender");
}

const std::string& ViewerLoop::TopicOf(const v1::Envelope& envelope) {
  const int body = static_cast<int>(envelope.body_case());
  for (const Topic& t : topics_) {
    if (t.body == body && t.sender == envelope.sender()) return t.name;
  }
  const std::string& sender = envelope.sender();
  // a sender name becomes part of a topic: only what a service name can be
  const bool plain = !sender.empty() && sender.size() <= 64 &&
                     sender.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-@.") == std::string::npos;
  if (!plain) {
    ++counters_.messages_unknown_sender;
    return unknown_topic_;
  }
  const auto* field = v1::Envelope::descriptor()->FindFieldByNumber(body);
  topics_.push_back({sender, body, codec::MessageTopic(sender, field != nullptr ? field->name() : "unknown")});
  return topics_.back().name;
}

std::uint64_t ViewerLoop::LogTimeNs(double t_s) const {
  return config_.epoch_at_start_ns + static_cast<std::uint64_t>(std::max(0.0, t_s) * 1e9);
}

void ViewerLoop::Read(const v1::Envelope& envelope, double t_s) {
  const std::uint64_t time_ns = LogTimeNs(t_s);
  const google::protobuf::Message* body = nullptr;
  switch (envelope.body_case()) {
    case v1::Envelope::kClothFrame:
      AssembleCloth(envelope.cloth_frame());
      body = &envelope.cloth_frame();
      break;
    case v1::Envelope::kFingerStates:
      fingers_ = envelope.finger_states();
      body = &envelope.finger_states();
      break;
    case v1::Envelope::kForceModel:
      forces_ = envelope.force_model();
      body = &envelope.force_model();
      break;
    case v1::Envelope::kTouchTrace:
      body = &envelope.touch_trace();
      break;
    case v1::Envelope::kPinFrame:
      body = &envelope.pin_frame();
      break;
    case v1::Envelope::kHealth:
      body = &envelope.health();
      break;
    default:
      return;  // patches, control and probes are not shown
  }
  const std::string& topic = TopicOf(envelope);
  if (&topic == &unknown_topic_) return;
  sink_->Publish(topic, *body, time_ns);
  ++counters_.messages_passed_on;
}

void ViewerLoop::AssembleCloth(const v1::ClothFrame& chunk) {
  const std::uint64_t n = static_cast<std::uint64_t>(chunk.particles_u()) * chunk.particles_v();
  const std::uint64_t first = chunk.first_particle();
  const std::uint64_t count = static_cast<std::uint64_t>(chunk.position_q_size()) / 3;
  // a chunk that does not fit its own grid is not drawn (hostile or corrupt); the largest grid a
  // scene allows (401 x 401) comes in 42 chunks
  if (n == 0 || n > (1u << 20) || first + count > n || chunk.chunk_count() == 0 || chunk.chunk_count() > 64 ||
      chunk.chunk_index() >= chunk.chunk_count()) {
    ++counters_.cloth_chunks_bad;
    return;
  }
  if (chunk.frame_index() != assembling_frame_ || chunk.particles_u() != u_ || chunk.particles_v() != v_ ||
      assembling_W_m_.size() != 3 * n) {
    assembling_frame_ = chunk.frame_index();
    u_ = chunk.particles_u();
    v_ = chunk.particles_v();
    assembling_W_m_.assign(3 * n, 0.0f);
    chunks_seen_ = 0;
  }
  // malformed positions (a bad step, a ragged or runaway sum) are refused whole
  if (codec::DecodeClothPositions(chunk, assembling_W_m_.data() + 3 * first, 3 * (n - first)) < 0) {
    ++counters_.cloth_chunks_bad;
    return;
  }
  assembling_patch_ = {chunk.patch_u_begin(), chunk.patch_u_end(), chunk.patch_v_begin(), chunk.patch_v_end()};
  chunks_seen_ |= std::uint64_t{1} << chunk.chunk_index();
  const std::uint64_t all =
      chunk.chunk_count() == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << chunk.chunk_count()) - 1;
  if (chunks_seen_ == all) {
    cloth_W_m_ = assembling_W_m_;
    patch_ = assembling_patch_;
    cloth_new_ = true;
    chunks_seen_ = 0;
    ++counters_.cloth_frames_whole;
  }
}

void ViewerLoop::Update(double t_s, double /*dt_s*/) {
  if (cloth_new_ && t_s >= next_scene_s_) {
    next_scene_s_ = t_s + 1.0 / config_.frame_hz;
    cloth_new_ = false;
    const std::uint64_t time_ns = LogTimeNs(t_s);
    sink_->Publish("/viewer/scene", scene_view_.Build(cloth_W_m_, u_, v_, patch_, fingers_, forces_, time_ns), time_ns);
    ++counters_.scene_updates;
  }
  PublishCounters();
}

void ViewerLoop::PublishCounters() {
  health_->SetCounter(ids_.passed, counters_.messages_passed_on);
  health_->SetCounter(ids_.whole, counters_.cloth_frames_whole);
  health_->SetCounter(ids_.bad, counters_.cloth_chunks_bad);
  health_->SetCounter(ids_.scenes, counters_.scene_updates);
  health_->SetCounter(ids_.unknown, counters_.messages_unknown_sender);
}

}  // namespace haptex::viewer
