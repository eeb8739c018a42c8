#pragma once

#include "haptex/v1/pin_frame.pb.h"

namespace haptex::mock_pins::testing {

/// A valid frame: thumb with a ramp on the 40 Hz channel, index silent.
inline v1::PinFrame RampFrame(std::uint64_t index) {
  v1::PinFrame frame;
  frame.set_frame_index(index);
  auto* thumb = frame.add_fingers();
  thumb->set_finger(v1::FINGER_THUMB);
  auto* finger = frame.add_fingers();
  finger->set_finger(v1::FINGER_INDEX);
  for (int i = 0; i < 24; ++i) {
    thumb->add_amplitude_40hz(static_cast<float>(i) / 23.0f);
    thumb->add_amplitude_320hz(0.0f);
    finger->add_amplitude_40hz(0.0f);
    finger->add_amplitude_320hz(0.0f);
  }
  return frame;
}

}  // namespace haptex::mock_pins::testing
