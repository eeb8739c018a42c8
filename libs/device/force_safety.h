#pragma once
// The last stage before the device: watchdog and start-up ramps, peak and continuous force
// limits, slew limit, NaN guard. One instance per manipulator.

#include <Eigen/Core>
#include <cstdint>

namespace haptex::device {

/// What the GRAB hardware can do (paper section 3.1); configs may only be stricter.
inline constexpr double kDevicePeakForce_N = 20.0;
inline constexpr double kDeviceContinuousForce_N = 6.0;
/// The force reaches zero at most this long after the last fresh ForceModel.
inline constexpr double kMaxForceModelSilence_s = 0.020;

/// Limits of the safety stage. Validate() throws std::invalid_argument with a clear message.
struct ForceSafetyConfig {
  double peak_force_N = 20.0;  ///< |F| never exceeds this (direction kept)
  /// RMS |F| over the window below never exceeds this (i^2 t style thermal limit). The allowed
  /// magnitude is peak when cold and falls linearly to this as the mean square approaches its square.
  double continuous_force_N = 6.0;
  /// Time constant of the exponentially weighted mean of |F|^2 used for the continuous limit.
  double continuous_window_s = 1.0;
  /// Slew: |F(k) - F(k-1)| <= min(slew_N_per_tick, slew_N_per_s x dt). Per unit of time, so a
  /// faster host moves no faster; per Step as well, so a host catching up after a stall (one long
  /// Step) moves no more than one step's worth.
  double slew_N_per_tick = 0.5;
  double slew_N_per_s = 2500.0;  ///< 0.5 N per 5 kHz tick, the controller's own limit
  double stale_after_s = 0.010;  ///< a ForceModel is fresh for min(ttl, this) after arrival
  double stale_ramp_s = 0.010;   ///< then the force ramps linearly to zero over this
  double startup_ramp_s = 0.5;   ///< force scales in linearly over this after (re)arming
  /// After a brief interruption of a fully armed stage (SafetyInput::link_interruption, or the
  /// watchdog's zero while output was allowed: models that fell silent on a paused host and came
  /// back), the force scales in over this instead (at most startup_ramp_s): the user still holds the device
  /// where the force was, and a slow ramp lets squeezing fingers close through the virtual object
  /// onto the stiff finger-finger spring. 5 ms is short against that motion, yet for a 2 N pinch
  /// only 400 N/s, a sixth of the slew limit: no jump back to the old force.
  double resume_ramp_s = 0.005;
  /// Interruptions longer than this (summed until the force is back at full scale) ramp in over
  /// startup_ramp_s again. Longer than the pauses a virtual machine takes now and then (up to
  /// 63 ms seen), so that such a pause resumes the contact at its proxies (ResumeProxy).
  double resume_within_s = 0.100;
  /// So do interruptions over which the finger moved farther than this from where it last had
  /// force: the user no longer holds it where the force was (a squeeze that went on while only
  /// the models stalled has closed the fingers onto, or past, each other), and the model would
  /// answer the new place at once with a force the hand never felt build up.
  double resume_within_m = 0.002;

  void Validate() const;
};

/// Inputs of one safety step.
struct SafetyInput {
  Eigen::Vector3d requested_W_N{Eigen::Vector3d::Zero()};  ///< evaluated ForceModel (may be NaN)
  double model_age_s = 0.0;                                ///< now minus arrival of the model; +inf if there is none
  double model_ttl_s = 0.0;                                ///< the model's own ttl
  bool output_allowed = false;                             ///< device present, calibrated, not shut down
  /// Output is off only because the link to the controller hiccupped (the host's own loop stalled,
  /// or the controller reported that commands stopped reaching it); the device is still there.
  bool link_interruption = false;
  Eigen::Vector3d p_W_m{Eigen::Vector3d::Zero()};  ///< the finger's position now
};

/// Result of one safety step.
struct SafetyOutput {
  Eigen::Vector3d force_W_N{Eigen::Vector3d::Zero()};
  bool limited = false;  ///< peak, continuous or slew limit changed the force
  bool ramping = false;  ///< start-up or watchdog ramp below full scale
};

/// Counters of everything the stage changed (one count per Step in which it happened).
struct SafetyCounters {
  std::uint64_t steps = 0;
  std::uint64_t non_finite = 0;  ///< NaN/Inf request replaced by zero
  std::uint64_t peak_limited = 0;
  std::uint64_t continuous_limited = 0;
  std::uint64_t slew_limited = 0;
  std::uint64_t stale_steps = 0;          ///< model older than its freshness limit
  std::uint64_t watchdog_zero_steps = 0;  ///< force held at zero by the watchdog
};

/// Per-manipulator safety stage. Order: NaN -> ramps (watchdog x start-up) -> peak and continuous
/// clamp -> slew -> final envelope. The envelope is a magnitude cap applied after the slew limit,
/// so zero force is reached on time whatever the slew limit: safety wins over smoothness.
class ForceSafety {
 public:
  /// @throws std::invalid_argument if `config` is invalid.
  explicit ForceSafety(const ForceSafetyConfig& config);

  /// One tick: `dt_s` is the time since the previous Step (used by the continuous limit and the
  /// start-up ramp; the slew limit is per Step).
  SafetyOutput Step(const SafetyInput& input, double dt_s);

  /// Back to the just-constructed state (zero force, unarmed, empty continuous average).
  void Reset();

  const ForceSafetyConfig& config() const { return config_; }
  const SafetyCounters& counters() const { return counters_; }
  /// Current estimate of the RMS force over the continuous window [N].
  double rms_force_N() const;
  const Eigen::Vector3d& last_force_W_N() const { return previous_W_N_; }

  /// The watchdog's scale for a model of this age and ttl: 1 while fresh, then down to 0 over
  /// stale_ramp_s.
  double WatchdogGain(const SafetyInput& input) const;

 private:
  ForceSafetyConfig config_;
  SafetyCounters counters_;
  Eigen::Vector3d previous_W_N_{Eigen::Vector3d::Zero()};
  double mean_square_N2_ = 0.0;
  double armed_s_ = 0.0;
  bool resumable_ = false;      ///< reached full scale, only brief interruptions (link or models) since
  double interrupted_s_ = 0.0;  ///< time without output since full scale was last reached
  Eigen::Vector3d armed_p_W_m_{Eigen::Vector3d::Zero()};  ///< the finger's position when it last had the whole force
};

}  // namespace haptex::device
