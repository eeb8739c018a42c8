#include "services/in_process/in_process_system.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "libs/codec/message_conversion.h"
#include "libs/dual_layer/refined_grid.h"
#include "libs/scene/cloth_setup.h"
#include "libs/scene/scene_contact.h"
#include "libs/scene/scene_defaults.h"
#include "libs/scene/scene_device.h"
#include "services/mock_grab/mock_user.h"

namespace haptex::in_process {

LinkImpairments LinkImpairments::HapticLink(const netsim::ImpairmentConfig& each_way, std::uint64_t seed) {
  LinkImpairments links;
  links.bridge_to_local = links.local_to_bridge = links.bridge_to_global = each_way;
  links.seed = seed;
  return links;
}

LinkImpairments LinkImpairments::GlobalLink(const netsim::ImpairmentConfig& each_way, std::uint64_t seed) {
  LinkImpairments links;
  links.global_to_local = links.local_to_global = links.bridge_to_global = each_way;
  links.seed = seed;
  return links;
}

// One direction of a link: messages in flight, released when the impairment model says.
class InProcessSystem::Link {
 public:
  Link(const netsim::ImpairmentConfig& config, std::uint64_t seed, Node to) : model_(config, seed), to_(to) {}

  void Send(std::int64_t now_ns, const google::protobuf::MessageLite& body, int field) {
    if (cut_) return;
    std::string bytes = body.SerializeAsString();
    const netsim::Decision d = model_.Decide(now_ns, bytes.size() + 60);  // with the envelope's framing
    ++sequence_;
    for (int c = 0; c < d.copies; ++c) {
      queue_.push(
          {d.release_ns[static_cast<std::size_t>(c)], order_++, sequence_, d.sequence, d.arrival_ns, field, bytes});
    }
  }
  /// Calls deliver(envelope) for every message due by `now_ns`, in release order.
  template <class Deliver>
  void DeliverDue(std::int64_t now_ns, Deliver&& deliver) {
    while (!queue_.empty() && queue_.top().release_ns <= now_ns) {
      const InFlight m = queue_.top();
      queue_.pop();
      model_.OnDelivered(m.model_sequence, m.arrival_ns, now_ns);
      v1::Envelope envelope;
      envelope.set_version(1);
      envelope.set_sender_epoch(1);
      envelope.set_sequence(m.sequence);
      const auto* field = v1::Envelope::descriptor()->FindFieldByNumber(m.field);
      envelope.GetReflection()->MutableMessage(&envelope, field)->ParseFromString(m.bytes);
      deliver(envelope);
    }
  }
  Node to() const { return to_; }
  void SetCut(bool cut) { cut_ = cut; }

 private:
  struct InFlight {
    std::int64_t release_ns;
    std::uint64_t order;  // ties leave in the order sent
    std::uint64_t sequence, model_sequence;
    std::int64_t arrival_ns;
    int field;
    std::string bytes;
    bool operator>(const InFlight& o) const {
      return release_ns != o.release_ns ? release_ns > o.release_ns : order > o.order;
    }
  };
  netsim::ImpairmentModel model_;
  Node to_;
  bool cut_ = false;
  std::uint64_t sequence_ = 0, order_ = 0;
  std::priority_queue<InFlight, std::vector<InFlight>, std::greater<>> queue_;
};

// What a node's loop sends: each peer id is one link.
class InProcessSystem::NodeOutbox final : public services::Outbox {
 public:
  NodeOutbox(const InProcessSystem* system, std::vector<Link*> links) : system_(system), links_(std::move(links)) {}

 protected:
  bool SendBody(services::PeerId peer, const google::protobuf::MessageLite& body, int field) override {
    if (peer >= links_.size() || links_[peer] == nullptr) return false;
    links_[peer]->Send(std::llround(system_->t_s() * 1e9), body, field);
    return true;
  }

 private:
  const InProcessSystem* system_;
  std::vector<Link*> links_;
};

namespace {
constexpr services::PeerId kFirstPeer = 0, kSecondPeer = 1;
}  // namespace

InProcessSystem::InProcessSystem(const scene::LoadedScene& scene, const LinkImpairments& links)
    : dt_s_(1.0 / device::kControllerRate_Hz),
      local_every_(static_cast<int>(std::lround(device::kControllerRate_Hz / scene::LocalRateHz(scene.scene)))),
      global_every_(static_cast<int>(std::lround(device::kControllerRate_Hz / scene::GlobalRateHz(scene.scene)))),
      mock_health_("mock_grab"),
      bridge_health_("device_bridge"),
      local_health_("local_contact"),
      global_health_("global_sim") {
  const v1::Scene& sc = scene.scene;
  device::MockControllerConfig mock_config;
  mock_ = std::make_unique<mock_grab::MockGrabLoop>(mock_config, mock_grab::MockUser(sc, "", "", mock_config), nullptr,
                                                    0, &mock_health_);
  const device_bridge::BridgeLoopConfig bridge_config{scene::BridgeConfigFromScene(sc), device::kControllerRate_Hz,
                                                      scene::FingerStatesToLocalHz(sc),
                                                      scene::FingerStatesToGlobalHz(sc), true};
  bridge_ = std::make_unique<device_bridge::BridgeLoop>(
      bridge_config, device_bridge::BridgePeers{kFirstPeer, kSecondPeer, std::nullopt}, &bridge_health_);
  const scene::ClothSetup setup = scene::MakeClothSetup(scene);
  const double local_hz = scene::LocalRateHz(sc);
  local_contact::PatchBuildSpec spec{setup.material, setup.model_options, scene::LocalStepOptions(sc, local_hz),
                                     scene::ContactOptionsFromScene(scene), 0};
  spec.particle_id_space =
      static_cast<int>(dual_layer::MakeRefinedGrid(setup.grid.particles_warp, setup.grid.particles_weft,
                                                   static_cast<int>(sc.model().patch_refinement()))
                           .id_space());
  builder_ = std::make_unique<local_contact::PatchBuilder>(spec, local_contact::PatchBuilder::Threading::kCallerRuns);
  const local_contact::LocalContactConfig local_config{local_hz, scene::SceneFingers(sc), scene::ForceModelStaleS(sc)};
  local_ = std::make_unique<local_contact::LocalContactLoop>(
      local_config, local_contact::LocalContactPeers{kFirstPeer, kSecondPeer, std::nullopt, std::nullopt},
      builder_.get(), &local_health_);
  global_ = std::make_unique<global_sim::GlobalSimLoop>(
      scene, scene::GlobalRateHz(sc), global_sim::GlobalSimPeers{kFirstPeer, std::nullopt}, &global_health_);

  const auto link = [&](const netsim::ImpairmentConfig& config, Node to) {
    links_.push_back(std::make_unique<Link>(config, links.seed + links_.size(), to));
    return links_.back().get();
  };
  Link* bridge_to_local = link(links.bridge_to_local, Node::kLocal);
  Link* bridge_to_global = link(links.bridge_to_global, Node::kGlobal);
  Link* local_to_bridge = link(links.local_to_bridge, Node::kBridge);
  Link* local_to_global = link(links.local_to_global, Node::kGlobal);
  Link* global_to_local = link(links.global_to_local, Node::kLocal);
  // peer ids as the loops were given them above
  outboxes_[static_cast<std::size_t>(Node::kBridge)] =
      std::make_unique<NodeOutbox>(this, std::vector<Link*>{bridge_to_local, bridge_to_global});
  outboxes_[static_cast<std::size_t>(Node::kLocal)] =
      std::make_unique<NodeOutbox>(this, std::vector<Link*>{local_to_bridge, local_to_global});
  outboxes_[static_cast<std::size_t>(Node::kGlobal)] =
      std::make_unique<NodeOutbox>(this, std::vector<Link*>{global_to_local});
  // the launcher enables force once every service is up
  bridge_->OnControl(v1::Control::COMMAND_ENABLE_FORCE);
  // the scene's pauses on purpose, as the launcher carries them out (tactile and the viewer are
  // not simulated here)
  for (const v1::Stall& stall : sc.stalls()) {
    StallTarget target = StallTarget::kAll;
    switch (stall.service()) {
      case v1::ServicePlacement::SERVICE_MOCK_GRAB:
        target = StallTarget::kMockGrab;
        break;
      case v1::ServicePlacement::SERVICE_DEVICE_BRIDGE:
        target = StallTarget::kDeviceBridge;
        break;
      case v1::ServicePlacement::SERVICE_LOCAL_CONTACT:
        target = StallTarget::kLocalContact;
        break;
      case v1::ServicePlacement::SERVICE_GLOBAL_SIM:
        target = StallTarget::kGlobalSim;
        break;
      default:
        if (!stall.all()) continue;
    }
    AddStall(Stall{target, stall.at_s(), stall.duration_s()});
  }
}

InProcessSystem::~InProcessSystem() = default;

void InProcessSystem::CutNetwork(bool cut) {
  for (const auto& link : links_) link->SetCut(cut);
}

void InProcessSystem::Deliver(Node node) {
  const std::int64_t now_ns = std::llround(t_s() * 1e9);
  for (const auto& link : links_) {
    if (link->to() != node) continue;
    link->DeliverDue(now_ns, [&](const v1::Envelope& envelope) {
      switch (node) {
        case Node::kBridge:
          bridge_->Read(envelope, t_s());
          break;
        case Node::kLocal:
          local_->Read(envelope, t_s());
          break;
        case Node::kGlobal:
          global_->Read(envelope, t_s());
          break;
      }
    });
  }
}

void InProcessSystem::AddStall(const Stall& stall) {
  if (!(stall.at_s >= 0.0) || !std::isfinite(stall.at_s) || !(stall.duration_s >= 0.0) ||
      !std::isfinite(stall.duration_s)) {
    throw std::invalid_argument("InProcessSystem::AddStall: at_s and duration_s must be finite and >= 0");
  }
  stalls_.push_back(stall);
}

bool InProcessSystem::Paused(StallTarget target) const {
  const double t = t_s();
  for (const Stall& s : stalls_) {
    if ((s.target == target || s.target == StallTarget::kAll) && t >= s.at_s - 1e-9 &&
        t < s.at_s + s.duration_s - 1e-9) {
      return true;
    }
  }
  return false;
}

void InProcessSystem::StepMock(double t) {
  // what reached its socket while it was paused, oldest first (the newest valid command wins)
  for (const auto& command : command_queue_) mock_->ReadHost(command, t, true);
  command_queue_.clear();
  // one long step after a pause, as its loop takes after SIGCONT (the world stands still meanwhile)
  const double t_end = t + dt_s_;
  mock_->Update(mock_simulated_to_s_, t_end - mock_simulated_to_s_);
  mock_simulated_to_s_ = t_end;
}

void InProcessSystem::StepBridge(double t) {
  for (const QueuedStatus& status : status_queue_) bridge_->ReadController(status.bytes, status.arrival_s, t, true);
  status_queue_.clear();
  Deliver(Node::kBridge);
  // the whole time since its last tick, as its loop reports a stall's skipped periods
  const double dt = bridge_ran_ ? static_cast<double>(step_ - bridge_last_step_) * dt_s_ : dt_s_;
  bridge_->Update(t, dt);
  bridge_->Write(*outboxes_[static_cast<std::size_t>(Node::kBridge)]);
  bridge_last_step_ = step_;
  bridge_ran_ = true;
}

void InProcessSystem::Step() {
  const double t = t_s();
  const bool mock_paused = Paused(StallTarget::kMockGrab), bridge_paused = Paused(StallTarget::kDeviceBridge);
  // the controller, and the bridge over the GRAB link (a cable: no impairment)
  if (!mock_paused) StepMock(t);
  if (bridge_paused) {
    if (!mock_paused) {
      QueuedStatus& queued = status_queue_.emplace_back();
      std::copy(mock_->status().begin(), mock_->status().end(), queued.bytes.begin());
      queued.arrival_s = t;
    }
  } else {
    if (!mock_paused) bridge_->ReadController(mock_->status(), t, t, true);
    StepBridge(t);
    if (mock_paused) {
      auto& queued = command_queue_.emplace_back();
      std::copy(bridge_->command().begin(), bridge_->command().end(), queued.begin());
    } else {
      mock_->ReadHost(bridge_->command(), t, true);
    }
  }
  // a paused service runs at once when it goes on, then on its own schedule
  const bool local_paused = Paused(StallTarget::kLocalContact);
  if (!local_paused && (step_ % static_cast<std::uint64_t>(local_every_) == 0 || local_was_paused_)) {
    Deliver(Node::kLocal);
    while (builder_->RunOnce()) {
    }
    local_->Update(t, local_every_ * dt_s_);
    local_->Write(*outboxes_[static_cast<std::size_t>(Node::kLocal)]);
  }
  local_was_paused_ = local_paused;
  const bool global_paused = Paused(StallTarget::kGlobalSim);
  if (!global_paused && (step_ % static_cast<std::uint64_t>(global_every_) == 0 || global_was_paused_)) {
    Deliver(Node::kGlobal);
    global_->Update(t, global_every_ * dt_s_);
    global_->Write(*outboxes_[static_cast<std::size_t>(Node::kGlobal)]);
  }
  global_was_paused_ = global_paused;
  for (int f = 0; f < 2; ++f) {
    const device::MockFingerState& s = mock_->controller().finger(static_cast<device::Manipulator>(f));
    FingerSample& sample = fingers_[static_cast<std::size_t>(f)];
    sample.commanded_N = s.commanded_force_D_N;
    sample.applied_N = s.applied_force_D_N;
    sample.velocity_m_per_s = s.v_D_m_per_s;
    sample.position_m = s.p_D_m;
    if (!mock_paused) energy_J_[static_cast<std::size_t>(f)] += s.applied_force_D_N.dot(s.v_D_m_per_s) * dt_s_;
  }
  ++step_;
}

void InProcessSystem::RunUntil(double t_s) {
  while (this->t_s() < t_s) Step();
}

}  // namespace haptex::in_process
