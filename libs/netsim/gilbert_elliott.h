#pragma once
// Gilbert-Elliott burst loss: a two-state Markov chain stepped once per datagram. In the good
// state datagrams are lost with probability loss_good, in the bad state with loss_bad. With the
// defaults (loss_good 0, loss_bad 1) the stationary loss rate is p / (p + r) and losses come in
// bursts of mean length 1 / r.

namespace haptex::netsim {

struct GilbertElliottConfig {
  double p_good_to_bad = 0.0;  // P(good -> bad) per datagram; 0: the chain never leaves good
  double p_bad_to_good = 1.0;  // P(bad -> good) per datagram
  double loss_good = 0.0;      // loss probability in the good state
  double loss_bad = 1.0;       // loss probability in the bad state

  /// True when the chain can lose anything.
  bool enabled() const { return p_good_to_bad > 0.0 || loss_good > 0.0; }
};

/// Throws std::invalid_argument naming the parameter (prefix + "p", "r", "loss_good",
/// "loss_bad"); r must be > 0 when p > 0, or the bad state would never end.
void ValidateGilbertElliott(const GilbertElliottConfig& config, const char* prefix);

class GilbertElliott final {
 public:
  explicit GilbertElliott(const GilbertElliottConfig& config) : config_(config) {}

  /// Decides the current datagram's fate in the current state, then moves the chain on.
  /// `u_loss` and `u_transition` are independent uniform draws in [0, 1). Returns true: lost.
  bool Step(double u_loss, double u_transition);

  bool bad() const { return bad_; }

 private:
  GilbertElliottConfig config_;
  bool bad_ = false;  // starts good
};

}  // namespace haptex::netsim
