#include "services/mock_pins/pin_heat_map.h"

#include <algorithm>
#include <cmath>

#include "services/mock_pins/pin_frame_check.h"

namespace haptex::mock_pins {
namespace {

constexpr char kScale[] = " .:-=+*#%@";
constexpr int kLevels = sizeof(kScale) - 2;  // index of the last character

char Shade(float amplitude) {
  const int level = static_cast<int>(std::lround(std::clamp(amplitude, 0.0f, 1.0f) * kLevels));
  return kScale[level];
}

}  // namespace

std::string RenderPinHeatMap(const v1::PinFrame& frame) {
  std::string text;
  for (const v1::FingerPins& finger : frame.fingers()) {
    text += finger.finger() == v1::FINGER_THUMB ? "thumb  (40|320 Hz)\n" : "index  (40|320 Hz)\n";
    for (int row = 0; row < kPinRows; ++row) {
      text += "  |";
      for (int column = 0; column < kPinColumns; ++column) {
        const int pin = row * kPinColumns + column;
        text += Shade(finger.amplitude_40hz(pin));
        text += Shade(finger.amplitude_320hz(pin));
        text += '|';
      }
      text += '\n';
    }
  }
  return text;
}

}  // namespace haptex::mock_pins
