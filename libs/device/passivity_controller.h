#pragma once
// Time-domain passivity at the device port, per finger: a passivity observer sums the energy the
// rendered environment has taken from the finger (-F . v dt), and while that sum is negative (the
// environment gave the finger energy it never received: a model rendered late over a delayed link,
// a contact switching state) a passivity controller adds just enough damping to dissipate the
// deficit. Whatever the link's delay and whatever the model's error, the force then cannot pump
// energy into the finger; a transparent link (energy balance >= 0) is left alone.

#include <Eigen/Core>
#include <cstdint>

namespace haptex::device {

struct PassivityConfig {
  bool enabled = true;
  /// Largest damping the controller adds [N s/m]: 1/10 of the damping that would make a 0.1 kg
  /// fingertip's explicit step unstable at 5 kHz (m / dt = 500 N s/m), so the controller itself
  /// cannot oscillate.
  double max_damping_N_s_per_m = 50.0;
  /// The energy the environment may hold for the finger [J]: what it has taken beyond this is
  /// forgotten, so a long stretch of lossy contact does not bank credit that would let a later
  /// active phase through unchecked. More than a squeezed grip stores (5 N on 1.25 N/mm: 10 mJ).
  double max_reserve_J = 0.05;
  /// Below this speed the deficit waits (no damping can dissipate it without motion) [m/s].
  double min_speed_m_per_s = 1e-4;
  /// A deficit this small is left alone [J]: the force acts a few ticks before the displacement it
  /// causes is measured (the controller's force lag, the frame's latency), so even a passive
  /// contact shows small deficits at its stiffness; damping them would put damping into every grip.
  double deficit_tolerance_J = 0.003;

  void Validate() const;
};

struct PassivityCounters {
  std::uint64_t damped_steps = 0;  ///< steps in which damping was added
  double dissipated_J = 0.0;       ///< energy the controller has taken out
};

class PassivityController {
 public:
  explicit PassivityController(const PassivityConfig& config);

  /// The force to command instead of `requested_W_N` for a finger moving at `v_W_m_per_s`: the
  /// request plus the damping the current deficit needs over `dt_s`.
  Eigen::Vector3d Adjust(const Eigen::Vector3d& requested_W_N, const Eigen::Vector3d& v_W_m_per_s, double dt_s);
  /// Books the force commanded over the finger's last measured displacement (position differences
  /// sum exactly, where a quantised velocity's noise would walk the balance).
  void Observe(const Eigen::Vector3d& commanded_W_N, const Eigen::Vector3d& displacement_W_m);
  /// Forgets the balance (the finger left all contact, the device was lost or re-armed).
  void Reset() { energy_J_ = 0.0; }

  /// Energy the environment has taken from the finger, capped at max_reserve_J [J]; negative: it
  /// has given more than it took.
  double energy_J() const { return energy_J_; }
  const PassivityCounters& counters() const { return counters_; }

 private:
  PassivityConfig config_;
  double energy_J_ = 0.0;
  PassivityCounters counters_;
};

}  // namespace haptex::device
