#pragma once
// The logic of haptex-mock-grab: a simulated GRAB controller that speaks the real protocol.
// Each fingertip is a mass-spring-damper pulled by a scripted "artificial user" and pushed by the
// rendered force (closed loop). services/mock_grab wraps it with a socket and a 5 kHz loop.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "libs/device/deterministic_rng.h"
#include "libs/device/grab_protocol.h"
#include "libs/device/mock_script.h"

namespace haptex::device {

/// Fingertip + end-effector dynamics and the artificial user's grip on it.
struct MockFingerParams {
  double mass_kg = 0.1;                   ///< fingertip, gimbal and moving links
  double user_stiffness_N_per_m = 300.0;  ///< pull toward the scripted target
  double user_damping_N_s_per_m = 4.0;    ///< toward the target's velocity
  double device_damping_N_s_per_m = 0.5;  ///< viscous friction of the mechanism
  double force_time_constant_s = 0.0005;  ///< inner force loop: first-order lag to the command
};

/// Mock controller settings. Validate() throws std::invalid_argument with a clear message.
struct MockControllerConfig {
  MockFingerParams finger;
  double position_quantum_m = 0.032e-3;  ///< encoder resolution (paper section 3.1)
  double force_noise_N = 0.1;            ///< sensor noise, uniform in +-this per axis
  std::uint64_t seed = 1;                ///< noise seed: equal seeds give equal runs
  double host_timeout_s = 0.005;         ///< no valid command this long: zero force
  /// Sequence of the first StatusFrame (a real controller may start anywhere but 0); tests start
  /// near 2^32 to cross the wrap.
  std::uint32_t first_status_sequence = 1;
  double peak_force_N = 20.0;  ///< the controller's own clamp
  /// The controller's own slew limit on what it drives towards (a cut to zero is immediate): a
  /// controller that stalled and then takes the newest of many queued commands moves to it at
  /// this rate, not in one step. 2.5 kN/s: 0.5 N per 5 kHz tick, the host's own limit.
  double slew_N_per_s = 2500.0;
  /// The longest step the simulated world takes. A longer Step means the mock's own process did
  /// not run (a busy or throttled host): the world pauses for the rest, and the host's silence is
  /// counted only over time the controller ran. A real controller never stalls; a world that ran
  /// on through the mock's stall, with the watchdog blaming the host, would let the fingers fall
  /// into the fabric for longer than any device would, and the force comes back higher.
  double max_world_step_s = 0.001;
  /// Workspace box (also used to check commands); positions are stopped at its faces.
  GrabValueLimits limits;

  void Validate() const;
};

/// True (unquantised) state of one simulated fingertip, frame D.
struct MockFingerState {
  Eigen::Vector3d p_D_m{Eigen::Vector3d::Zero()};
  Eigen::Vector3d v_D_m_per_s{Eigen::Vector3d::Zero()};
  Eigen::Vector3d applied_force_D_N{Eigen::Vector3d::Zero()};  ///< what the motors apply now
  Eigen::Vector3d commanded_force_D_N{Eigen::Vector3d::Zero()};
  std::uint16_t flags = 0;
};

struct MockCounters {
  std::uint64_t steps = 0;
  std::uint64_t host_timeouts = 0;          ///< transitions into host timeout
  std::uint64_t commands_out_of_order = 0;  ///< valid command, sequence not newer: ignored
  std::uint64_t world_pauses = 0;           ///< Steps longer than max_world_step_s (own stalls)
};

/// Simulated GRAB controller. Host time and controller time are the same simulated clock here.
class MockGrabController {
 public:
  /// Fingers start at rest at the script's pose for t = 0.
  /// @throws std::invalid_argument if `config` or `script` is invalid.
  MockGrabController(const MockControllerConfig& config, ScriptParams script);

  /// Decodes one host datagram received at `t_s`; valid, newer commands replace the current one.
  FrameError OnCommandDatagram(std::span<const std::byte> datagram, double t_s);

  /// Advances the simulation from `t_s` by `dt_s` and writes the StatusFrame for time t_s + dt_s.
  void Step(double t_s, double dt_s, std::span<std::byte, kStatusFrameSize> out);

  const MockFingerState& finger(Manipulator m) const { return fingers_[static_cast<std::size_t>(m)]; }
  /// Moves a finger (tests, scene resets): position and velocity of the true state.
  void SetFinger(Manipulator m, const Eigen::Vector3d& p_D_m, const Eigen::Vector3d& v_D_m_per_s);
  bool host_timed_out() const { return host_timed_out_; }
  /// Sequence of the host command in force now, 0 before the first.
  std::uint32_t host_sequence() const { return has_command_ ? command_.sequence : 0; }
  const FrameCounters& frame_counters() const { return frame_counters_; }
  /// Valid CommandFrames newer than the one in force: the ones it took.
  std::uint64_t commands_accepted() const { return frame_counters_.accepted() - counters_.commands_out_of_order; }
  const MockCounters& counters() const { return counters_; }
  const ScriptParams& script() const { return script_; }

 private:
  MockControllerConfig config_;
  ScriptParams script_;
  DeterministicRng rng_;
  std::array<MockFingerState, kManipulatorCount> fingers_{};
  std::array<Eigen::Quaterniond, kManipulatorCount> q_DF_{};
  CommandFrame command_;
  bool has_command_ = false;
  // the host watchdog runs on the controller's running time: wall time less its own stalls
  double paused_s_ = 0.0;
  double last_command_run_s_ = 0.0;
  bool host_timed_out_ = true;
  bool command_rejected_ = false;
  std::uint32_t sequence_ = 0;
  FrameCounters frame_counters_;
  MockCounters counters_;
};

}  // namespace haptex::device
