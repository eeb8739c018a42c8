#pragma once
// Every loop of a run in one process, stepped on one simulated clock, with the messages between
// them carried by simulated links (libs/netsim: delay, jitter, loss, ...): the mock controller,
// the device bridge, local_contact (its patches built on the caller's thread) and global_sim.
// The same loop objects the services run, the same messages, the GRAB datagrams between the mock
// controller and the bridge: only the sockets and the wall clock are replaced, so a run is exactly
// repeatable. Tests use it to check the haptic link under delay and loss deterministically;
// benchmarks to sweep impairments fast. (The real processes through `haptex relay` are the
// reference: tests/launch, bench/remote.)

#include <array>
#include <cstdint>
#include <memory>
#include <queue>
#include <string>
#include <vector>

#include "libs/netsim/impairment_config.h"
#include "libs/netsim/impairment_model.h"
#include "libs/runtime/health_reporter.h"
#include "libs/scene/scene_loader.h"
#include "services/device_bridge/bridge_loop.h"
#include "services/global_sim/global_sim_loop.h"
#include "services/local_contact/local_contact_loop.h"
#include "services/local_contact/patch_builder.h"
#include "services/mock_grab/mock_grab_loop.h"

namespace haptex::in_process {

/// What the network does to each link, per direction. "up": from the device side (the bridge)
/// towards the simulation; "down": back.
struct LinkImpairments {
  netsim::ImpairmentConfig bridge_to_local, local_to_bridge;  ///< the haptic-rate link
  netsim::ImpairmentConfig bridge_to_global;                  ///< FingerStates at the global rate
  netsim::ImpairmentConfig global_to_local, local_to_global;  ///< patches and results
  std::uint64_t seed = 1;
  /// The same impairment on the bridge <-> local_contact link both ways (and on bridge -> global_sim,
  /// which shares its route when the simulation runs on another machine).
  static LinkImpairments HapticLink(const netsim::ImpairmentConfig& each_way, std::uint64_t seed = 1);
  /// The same impairment between local_contact and global_sim both ways (the bridge and
  /// local_contact together).
  static LinkImpairments GlobalLink(const netsim::ImpairmentConfig& each_way, std::uint64_t seed = 1);
};

/// A service's process, or the whole host, as a stall pauses it.
enum class StallTarget { kMockGrab, kDeviceBridge, kLocalContact, kGlobalSim, kAll };

/// A pause of the host on purpose: from at_s for duration_s the target neither reads, computes nor
/// sends, as after SIGSTOP; what is sent to it waits in its socket and it takes it all when it goes
/// on, with one long period, as after SIGCONT. kAll pauses the mock controller too, whose world
/// then stands still (a real controller is another machine: pause kDeviceBridge, kLocalContact and
/// kGlobalSim for a host that stops while the device goes on).
struct Stall {
  StallTarget target = StallTarget::kAll;
  double at_s = 0.0;
  double duration_s = 0.0;
};

/// One controller period's view of what the fingers felt (frame D = W).
struct FingerSample {
  Eigen::Vector3d commanded_N{Eigen::Vector3d::Zero()};
  Eigen::Vector3d applied_N{Eigen::Vector3d::Zero()};
  Eigen::Vector3d velocity_m_per_s{Eigen::Vector3d::Zero()};
  Eigen::Vector3d position_m{Eigen::Vector3d::Zero()};
};

class InProcessSystem final {
 public:
  /// The scene's services at its rates (the bridge and the mock controller at 5 kHz).
  /// @throws std::invalid_argument for a scene the services refuse or a bad impairment.
  InProcessSystem(const scene::LoadedScene& scene, const LinkImpairments& links);
  ~InProcessSystem();
  InProcessSystem(const InProcessSystem&) = delete;
  InProcessSystem& operator=(const InProcessSystem&) = delete;

  /// One controller period (0.2 ms): the mock steps, the bridge reads, computes and commands,
  /// local_contact and global_sim tick when due, and due messages are delivered.
  void Step();
  /// While `cut`, every link between the services loses everything sent (a cable pulled, a route
  /// gone); messages already in flight still arrive.
  void CutNetwork(bool cut);
  /// Steps until `t_s`.
  void RunUntil(double t_s);
  /// Pauses `stall.target` over [at_s, at_s + duration_s) of the simulated clock.
  /// @throws std::invalid_argument for a negative or non-finite time.
  void AddStall(const Stall& stall);

  double t_s() const { return static_cast<double>(step_) * dt_s_; }
  double dt_s() const { return dt_s_; }
  /// Finger 0 thumb, 1 index, after the last Step.
  const FingerSample& finger(int slot) const { return fingers_[static_cast<std::size_t>(slot)]; }
  /// Energy the device has put into each finger so far: sum of applied force . velocity dt [J].
  double energy_into_finger_J(int slot) const { return energy_J_[static_cast<std::size_t>(slot)]; }

  const device_bridge::BridgeLoop& bridge() const { return *bridge_; }
  const local_contact::LocalContactLoop& local_contact() const { return *local_; }
  const global_sim::GlobalSimLoop& global_sim() const { return *global_; }
  const mock_grab::MockGrabLoop& mock() const { return *mock_; }
  const runtime::HealthReporter& bridge_health() const { return bridge_health_; }
  runtime::HealthReporter& bridge_health() { return bridge_health_; }

  class Link;  // one direction of a simulated network link

 private:
  enum class Node { kBridge, kLocal, kGlobal };
  class NodeOutbox;
  void Deliver(Node node);
  bool Paused(StallTarget target) const;
  void StepMock(double t);
  void StepBridge(double t);

  // StatusFrames that reached a paused bridge's socket, with their arrival (the kernel's stamp)
  struct QueuedStatus {
    std::array<std::byte, device::kStatusFrameSize> bytes;
    double arrival_s;
  };

  double dt_s_;
  std::uint64_t step_ = 0;
  int local_every_, global_every_;
  runtime::HealthReporter mock_health_, bridge_health_, local_health_, global_health_;
  std::unique_ptr<mock_grab::MockGrabLoop> mock_;
  std::unique_ptr<device_bridge::BridgeLoop> bridge_;
  std::unique_ptr<local_contact::PatchBuilder> builder_;
  std::unique_ptr<local_contact::LocalContactLoop> local_;
  std::unique_ptr<global_sim::GlobalSimLoop> global_;
  std::vector<std::unique_ptr<Link>> links_;
  std::array<std::unique_ptr<NodeOutbox>, 3> outboxes_;
  std::array<FingerSample, 2> fingers_{};
  std::array<double, 2> energy_J_{};
  std::vector<Stall> stalls_;
  std::vector<QueuedStatus> status_queue_;                                       // to a paused bridge
  std::vector<std::array<std::byte, device::kCommandFrameSize>> command_queue_;  // to a paused mock
  double mock_simulated_to_s_ = 0.0;                                             // the mock's world has run up to here
  std::uint64_t bridge_last_step_ = 0;
  bool bridge_ran_ = false, local_was_paused_ = false, global_was_paused_ = false;
};

}  // namespace haptex::in_process
