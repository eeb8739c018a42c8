#include "services/mock_pins/pin_frame_check.h"

#include <cmath>

namespace haptex::mock_pins {

PinFrameProblem CheckPinFrame(const v1::PinFrame& frame) {
  if (frame.fingers_size() == 0) return PinFrameProblem::kNoFingers;
  if (frame.fingers_size() > 2) return PinFrameProblem::kTooManyFingers;
  if (frame.fingers_size() == 2 && frame.fingers(0).finger() == frame.fingers(1).finger()) {
    return PinFrameProblem::kBadFinger;
  }
  for (const v1::FingerPins& finger : frame.fingers()) {
    if (finger.finger() != v1::FINGER_THUMB && finger.finger() != v1::FINGER_INDEX) {
      return PinFrameProblem::kBadFinger;
    }
    if (finger.amplitude_40hz_size() != kPinsPerFinger || finger.amplitude_320hz_size() != kPinsPerFinger) {
      return PinFrameProblem::kWrongPinCount;
    }
    for (int i = 0; i < kPinsPerFinger; ++i) {
      for (const float a : {finger.amplitude_40hz(i), finger.amplitude_320hz(i)}) {
        if (!std::isfinite(a) || a < 0.0f || a > 1.0f) return PinFrameProblem::kOutOfRange;
      }
    }
  }
  return PinFrameProblem::kNone;
}

std::string_view PinFrameProblemName(PinFrameProblem problem) {
  switch (problem) {
    case PinFrameProblem::kNone:
      return "none";
    case PinFrameProblem::kNoFingers:
      return "no_fingers";
    case PinFrameProblem::kTooManyFingers:
      return "too_many_fingers";
    case PinFrameProblem::kBadFinger:
      return "bad_finger";
    case PinFrameProblem::kWrongPinCount:
      return "wrong_pin_count";
    case PinFrameProblem::kOutOfRange:
      return "amplitude_out_of_range";
  }
  return "invalid";
}

}  // namespace haptex::mock_pins
