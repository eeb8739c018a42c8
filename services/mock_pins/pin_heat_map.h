#pragma once
// A 6 x 4 text heat map per finger, for watching a pin display in a terminal.

#include <string>

#include "haptex/v1/pin_frame.pb.h"

namespace haptex::mock_pins {

/// One block per finger: a title line, then 6 rows (row 0 distal) of 4 cells, each cell two
/// characters: the 40 Hz and the 320 Hz amplitude on the scale " .:-=+*#%@" (0 to 1).
/// The frame must have passed CheckPinFrame.
std::string RenderPinHeatMap(const v1::PinFrame& frame);

}  // namespace haptex::mock_pins
