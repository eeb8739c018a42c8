#pragma once
// The contact states of paper Table 1 and the classifier that names them, with hysteresis so a
// state does not chatter on a boundary.
//
// | fingers touch each other | no      | yes, static | yes, dynamic |
// | no textile contact       | I       | II          | III          |
// | one finger on textile    | IV / V (static / dynamic)            |
// | both fingers on textile  | VI / VII | VIII       | IX           |

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace haptex::contact {

enum class ContactState : std::uint8_t { kI = 1, kII, kIII, kIV, kV, kVI, kVII, kVIII, kIX };

const char* ToString(ContactState state);

/// What the models report before naming the state.
struct ContactEvidence {
  bool thumb_on_textile = false;
  bool index_on_textile = false;
  bool fingers_touch = false;  ///< directly or through squeezed fabric
  bool dynamic = false;        ///< the friction that matters in this situation slides
  /// The sliding share of that friction this tick, before the filter and hysteresis that decide
  /// `dynamic` (ContactOptions::state_filter_s): 0 (all sticks) .. 1 (all slides).
  double slip_fraction = 0.0;
};

/// Table 1. One finger on textile while the fingers touch each other (the table's "-") is named
/// IV/V: the finger-finger force is still rendered by its own model.
ContactState Classify(const ContactEvidence& evidence);

/// Hysteresis on a scalar: on above `enter`, off below `leave` (leave <= enter).
class Hysteresis {
 public:
  Hysteresis() = default;
  Hysteresis(double enter, double leave) : enter_(enter), leave_(leave) {}
  bool Update(double value) {
    on_ = on_ ? value >= leave_ : value > enter_;
    return on_;
  }
  bool on() const { return on_; }
  void Reset() { on_ = false; }

 private:
  double enter_ = 0.0, leave_ = 0.0;
  bool on_ = false;
};

/// Hysteresis on a low-passed scalar: y += (1 - exp(-dt / tau)) (x - y), then on above `enter`,
/// off below `leave`. Thresholds alone let a value that swings across both of them every few
/// ticks flip the state every few ticks (a hanging fabric bouncing on a resting finger, pinch
/// samples sticking and slipping in turn); the filter names such a contact by what it does on
/// average. A clean step still switches within about tau (0.92 tau for a share 0 -> 1 against
/// 0.6). With Rise::kAtOnce the filter follows any rise at once and only decays (a peak hold):
/// a contact is named on its first tick and kept through short gaps, released tau ln(peak /
/// leave) after its last load. tau = 0: no filter. Non-finite values are skipped (the filter
/// holds).
class FilteredHysteresis {
 public:
  enum class Rise { kFiltered, kAtOnce };
  FilteredHysteresis() = default;
  FilteredHysteresis(double enter, double leave, double time_constant_s, Rise rise = Rise::kFiltered)
      : hysteresis_(enter, leave), time_constant_s_(time_constant_s), rise_(rise) {}
  bool Update(double value, double dt_s) {
    if (std::isfinite(value)) {
      if (time_constant_s_ <= 0.0 || (rise_ == Rise::kAtOnce && value >= filtered_)) {
        filtered_ = value;
      } else {
        filtered_ += (1.0 - std::exp(-std::max(dt_s, 0.0) / time_constant_s_)) * (value - filtered_);
      }
    }
    return hysteresis_.Update(filtered_);
  }
  bool on() const { return hysteresis_.on(); }
  double filtered() const { return filtered_; }
  void Reset() {
    hysteresis_.Reset();
    filtered_ = 0.0;
  }

 private:
  Hysteresis hysteresis_;
  double time_constant_s_ = 0.0;
  Rise rise_ = Rise::kFiltered;
  double filtered_ = 0.0;
};

}  // namespace haptex::contact
