#pragma once
// How a held contact comes back after a cut of the force (a stall of the bridge that timed the
// controller out, models that fell silent, a link hiccup): a proxy ("god object") per finger.
//
// While the force was whole, the proxy is the finger. At a cut it stays on the surface the finger
// pressed, the plane through the finger's last position with the whole force, normal to that force:
// the user's fingers, no longer held, close by millimetres in 10 ms (through the cloth and past each
// other), the proxy never does. The contact models get the proxy's pose, so the cloth never sees
// fingers that passed through it, and the force after the cut is the model's force at the proxy
// plus a damped spring that pulls the finger back to it, never more than max(1.1 x held,
// held + 0.3 N) and never pulling. The proxy follows the finger wherever it moves away from the
// surface; once the finger is back on it, the proxy is the finger again. The cap holds for
// settle_s after the finger is back on the surface (watch_s after the cut at most; then, for a
// finger still past the surface, it rises at release_rate_N_per_s), or until the contact ends. A cut longer than the
// safety stage's resume_within_s ends the contact: no proxy, and the start-up ramp.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>

namespace haptex::device {

struct ResumeProxyConfig {
  double held_window_s = 0.100;  ///< the force held: its mean magnitude over this long before a cut
  double min_held_N = 0.3;       ///< a smaller force is no held contact: nothing to resume
  double bound_ratio = 1.1;      ///< the force after a cut never exceeds max(ratio x held,
  double bound_margin_N = 0.3;   ///< held + margin)
  /// The bound holds flat this long after the cut that began a resume (cuts within it, a host
  /// that stalls again and again, do not start it anew: a cap renewed by each stall held a grip
  /// at a fraction of the user's squeeze for 2.6 s, the finger sank 4 mm past its proxy, and
  /// the release became a +-9 N buzz).
  double watch_s = 1.0;
  /// The bound holds this long after the finger is back on the surface (and at most watch_s): a
  /// flat cap held on longer caught a user whose grip was still building up when the cut came
  /// (a squeeze above the cap let the fingers sink through the cloth in an impaired run).
  double settle_s = 0.100;
  /// A finger still past its proxy when watch_s is over (a user who squeezed harder than the
  /// bound) is not let go at once, the return spring's whole force on millimetres of depth a
  /// jolt: the bound rises at this rate [N/s], the proxy holds, and the spring brings the finger
  /// back; it is back on the surface before release_max_s more have passed, or the proxy gives up.
  double release_rate_N_per_s = 10.0;
  double release_max_s = 2.0;
  /// The return spring [N/m] and its damping [N s/m] from the finger to its proxy: 5 mm past the
  /// surface is 5 N, which the bound then holds to; the damping keeps the return from overshooting
  /// the surface (a 0.1 kg fingertip on the user's 300 N/m grip and this spring is critically
  /// damped near 2 sqrt(k m) = 20 N s/m).
  double spring_N_per_m = 1000.0;
  double damping_N_s_per_m = 20.0;
  double rejoin_m = 0.0002;     ///< the finger is back on its proxy within this
  double contact_end_N = 0.05;  ///< the model's force at the proxy below this: the contact ended
  /// A force model late beyond its link's rhythm (the contact's service paused, datagrams lost)
  /// is extrapolated no further than the bound of the force held before it was late: its
  /// linearisation, taken where the fingers were, answers their motion since with up to twice its
  /// force (kExtrapolationAllowance_N), a jolt in a stiff grip. The bound holds on for late_watch_s
  /// after models are fresh again: the first ones after a paused contact service answer a patch
  /// that missed its steps, in a stiff fold at 2.5x the hold. Late: older than late_model_s and
  /// than late_factor x the longest gap between models of the last second or so (a jittery link's
  /// own rhythm is no lateness).
  /// Off by default: during a grip that is building up, a late model's cap held the force at the
  /// level before while the squeeze went on, and the fingers closed through the strip (Fig. 10).
  bool cap_late_models = false;
  double late_model_s = 0.0015;
  double late_factor = 1.5;
  double late_watch_s = 0.100;

  void Validate() const;
};

/// The window of held force: the mean magnitude over held_window_s, in 5 ms buckets (no allocation).
class HeldForceWindow {
 public:
  void Add(double force_N, double dt_s, double window_s);
  double Mean() const;
  void Clear();

 private:
  static constexpr std::size_t kBuckets = 20;
  std::array<double, kBuckets> sum_N_s_{};
  std::array<double, kBuckets> time_s_{};
  std::size_t current_ = 0;
};

class ResumeProxy {
 public:
  enum class Phase : std::uint8_t { kFollowing, kCut, kResuming };

  /// A cut longer than `max_cut_s` ends the contact (ForceSafetyConfig::resume_within_s: the
  /// safety stage then ramps in over its start-up ramp).
  /// @throws std::invalid_argument if `config` or `max_cut_s` is invalid.
  ResumeProxy(const ResumeProxyConfig& config, double max_cut_s);

  /// Start of a tick: whether the force is cut now (output off, the models stale, or a stall of
  /// the bridge's own loop), `dt_s` since the last tick. Returns true on the tick a cut
  /// began from a held contact.
  bool BeginTick(bool cut, double dt_s);
  /// The proxy of a (measured or predicted) finger position: itself, or its projection onto the
  /// surface when it has passed it.
  Eigen::Vector3d Constrain(const Eigen::Vector3d& p_W_m) const;
  /// The force to request this tick from the model's force at the proxy: unchanged while
  /// following; after a cut the model's force plus the return spring, along the held force's
  /// side, within the bound. Sets limited() when the bound cut it down.
  Eigen::Vector3d Shape(const Eigen::Vector3d& model_at_proxy_W_N, const Eigen::Vector3d& p_W_m,
                        const Eigen::Vector3d& v_W_m_per_s);
  /// `force` within the bound while a resume is under way (after anything added to the shaped
  /// force, the passivity controller's damping among it); unchanged while following.
  Eigen::Vector3d ClampToBound(const Eigen::Vector3d& force);
  /// End of a tick: the force commanded and whether it was the whole force (no ramp, output on).
  void EndTick(const Eigen::Vector3d& commanded_W_N, const Eigen::Vector3d& p_W_m, bool whole_force, double dt_s);

  /// While following, with the model `model_age_s` after its arrival: `force` within the bound
  /// of the force held before the models were late, while late and late_watch_s after; unchanged
  /// without a held contact. Counts the ticks it shortened.
  Eigen::Vector3d CapLateModel(const Eigen::Vector3d& force, double model_age_s, double dt_s);
  /// A model arrived `interval_s` after the one before: the link's rhythm.
  void OnModelArrival(double interval_s);
  std::uint64_t late_model_caps() const { return late_model_caps_; }

  Phase phase() const { return phase_; }
  /// True while the contact models get the proxy instead of the finger.
  bool constraining() const { return phase_ != Phase::kFollowing && proxy_active_; }
  double held_N() const { return held_N_; }
  double bound_N() const;
  /// The largest force commanded since the last cut began, over the bound's flat second [N].
  double peak_since_cut_N() const { return peak_since_cut_N_; }
  /// The largest force the model and spring asked for since the last cut began, before the bound.
  double asked_since_cut_N() const { return asked_since_cut_N_; }
  bool limited_since_cut() const { return limited_since_cut_; }
  /// Cuts longer than max_cut_s: the contact ended.
  std::uint64_t contacts_ended() const { return contacts_ended_; }
  std::uint64_t cuts() const { return cuts_; }

 private:
  void EndContact();

  ResumeProxyConfig config_;
  double max_cut_s_;
  Phase phase_ = Phase::kFollowing;
  HeldForceWindow window_;
  double held_N_ = 0.0;
  Eigen::Vector3d surface_p_W_m_{Eigen::Vector3d::Zero()};  ///< a point of the surface
  Eigen::Vector3d inward_W_{Eigen::Vector3d::Zero()};       ///< unit, into the contact (against the force)
  Eigen::Vector3d last_whole_W_N_{Eigen::Vector3d::Zero()};
  Eigen::Vector3d last_whole_p_W_m_{Eigen::Vector3d::Zero()};
  bool has_whole_ = false;
  bool proxy_active_ = false;
  double cut_s_ = 0.0, rejoined_s_ = -1.0;  // rejoined: since the finger is back (< 0: not)
  double since_cut_s_ = 0.0;                // since the cut that began the resume
  double peak_since_cut_N_ = 0.0, asked_since_cut_N_ = 0.0;
  bool limited_since_cut_ = false;
  std::uint64_t contacts_ended_ = 0, cuts_ = 0, late_model_caps_ = 0;
  bool late_ = false;
  double longest_gap_s_ = 0.0;  ///< between models, decaying over about a second
  double late_held_N_ = 0.0;
  double late_watch_left_s_ = 0.0;
};

}  // namespace haptex::device
