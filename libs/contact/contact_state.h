#pragma once
// The contact states of paper Table 1 and the classifier that names them, with hysteresis so a
// state does not chatter on a boundary.
//
// | fingers touch each other | no      | yes, static | yes, dynamic |
// | no textile contact       | I       | II          | III          |
// | one finger on textile    | IV / V (static / dynamic)            |
// | both fingers on textile  | VI / VII | VIII       | IX           |

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

}  // namespace haptex::contact
