#include "services/mock_pins/pin_frame_csv.h"

#include <stdexcept>

#include "services/mock_pins/pin_frame_check.h"

namespace haptex::mock_pins {

PinFrameCsv::PinFrameCsv(const std::string& path) : out_(path) {
  if (!out_) throw std::runtime_error("cannot write pin log " + path);
  out_ << "time_s,frame_index,finger,pin,amplitude_40hz,amplitude_320hz\n";
}

void PinFrameCsv::Append(double time_s, const v1::PinFrame& frame) {
  for (const v1::FingerPins& finger : frame.fingers()) {
    const char* name = finger.finger() == v1::FINGER_THUMB ? "thumb" : "index";
    for (int pin = 0; pin < kPinsPerFinger; ++pin) {
      out_ << time_s << ',' << frame.frame_index() << ',' << name << ',' << pin << ',' << finger.amplitude_40hz(pin)
           << ',' << finger.amplitude_320hz(pin) << '\n';
    }
  }
}

}  // namespace haptex::mock_pins
