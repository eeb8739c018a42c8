#pragma once
// The mock display's record of what it was asked to play, one row per pin per frame:
// time_s,frame_index,finger,pin,amplitude_40hz,amplitude_320hz

#include <fstream>
#include <string>

#include "haptex/v1/pin_frame.pb.h"

namespace haptex::mock_pins {

class PinFrameCsv {
 public:
  /// Throws std::runtime_error when the file cannot be written.
  explicit PinFrameCsv(const std::string& path);
  void Append(double time_s, const v1::PinFrame& frame);
  void Flush() { out_.flush(); }

 private:
  std::ofstream out_;
};

}  // namespace haptex::mock_pins
