#include "libs/contact/contact_state.h"

namespace haptex::contact {

const char* ToString(ContactState state) {
  switch (state) {
    case ContactState::kI:
      return "I";
    case ContactState::kII:
      return "II";
    case ContactState::kIII:
      return "III";
    case ContactState::kIV:
      return "IV";
    case ContactState::kV:
      return "V";
    case ContactState::kVI:
      return "VI";
    case ContactState::kVII:
      return "VII";
    case ContactState::kVIII:
      return "VIII";
    case ContactState::kIX:
      return "IX";
  }
  return "?";
}

ContactState Classify(const ContactEvidence& e) {
  const int on_textile = (e.thumb_on_textile ? 1 : 0) + (e.index_on_textile ? 1 : 0);
  if (on_textile == 0) {
    if (!e.fingers_touch) return ContactState::kI;
    return e.dynamic ? ContactState::kIII : ContactState::kII;
  }
  if (on_textile == 1) return e.dynamic ? ContactState::kV : ContactState::kIV;
  if (!e.fingers_touch) return e.dynamic ? ContactState::kVII : ContactState::kVI;
  return e.dynamic ? ContactState::kIX : ContactState::kVIII;
}

}  // namespace haptex::contact
