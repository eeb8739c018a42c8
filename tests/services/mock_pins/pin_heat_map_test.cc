#include "services/mock_pins/pin_heat_map.h"

#include <gtest/gtest.h>

#include "tests/services/mock_pins/pin_test_frames.h"

namespace haptex::mock_pins {
namespace {

TEST(PinHeatMapTest, DrawsSixRowsOfFourCellsPerFinger) {
  const std::string text = RenderPinHeatMap(testing::RampFrame(3));
  EXPECT_EQ(text,
            // pin i plays i/23 at 40 Hz: level round(9 i / 23) of " .:-=+*#%@"; 320 Hz is silent
            "thumb  (40|320 Hz)\n"
            "  |  |  |. |. |\n"
            "  |: |: |: |- |\n"
            "  |- |= |= |= |\n"
            "  |+ |+ |+ |* |\n"
            "  |* |# |# |# |\n"
            "  |% |% |@ |@ |\n"
            "index  (40|320 Hz)\n"
            "  |  |  |  |  |\n"
            "  |  |  |  |  |\n"
            "  |  |  |  |  |\n"
            "  |  |  |  |  |\n"
            "  |  |  |  |  |\n"
            "  |  |  |  |  |\n");
}

}  // namespace
}  // namespace haptex::mock_pins
