// haptex-mock-pins: stands in for the two 6 x 4 pin displays. Receives PinFrames as a display
// would, refuses bad ones (counted), records what it was asked to play, and can show a live text
// heat map per finger.
//
// Receives: PinFrame (from tactile), Control. Sends: Health (to the launcher).

#include <spdlog/spdlog.h>

#include <chrono>
#include <iostream>
#include <memory>

#include "libs/base/clock.h"
#include "services/common/service_context.h"
#include "services/mock_pins/pin_frame_check.h"
#include "services/mock_pins/pin_frame_csv.h"
#include "services/mock_pins/pin_heat_map.h"

namespace haptex::mock_pins {
namespace {

struct Options {
  std::string log_csv;
  bool heat_map = false;
  double heat_map_hz = 10;
};

int Run(services::ServiceContext& context, const Options& options) {
  std::unique_ptr<PinFrameCsv> csv;
  if (!options.log_csv.empty()) csv = std::make_unique<PinFrameCsv>(options.log_csv);
  auto& health = context.health();
  const auto frames_counter = health.AddCounter("frames_played");
  const auto rejected_counter = health.AddCounter("frames_rejected");
  health.SetState(v1::Health::STATE_READY);

  std::uint64_t frames = 0, rejected = 0;
  v1::PinFrame latest;
  bool have_latest = false;
  std::int64_t next_heat_map_ns = 0;
  const auto heat_map_period_ns = static_cast<std::int64_t>(1e9 / options.heat_map_hz);

  while (!context.StopRequested(base::SteadyNowNs())) {
    context.messenger().WaitReadable(std::chrono::milliseconds(20));
    context.messenger().Drain([&](const v1::Envelope& envelope, const net::Messenger::Endpoint&) {
      if (context.HandleControl(envelope) != services::ServiceContext::ControlResult::kNotControl) return;
      if (envelope.body_case() != v1::Envelope::kPinFrame) return;
      const PinFrameProblem problem = CheckPinFrame(envelope.pin_frame());
      if (problem != PinFrameProblem::kNone) {
        ++rejected;
        context.rt_log().Push(runtime::RtLogLevel::kWarn, "pin frame rejected, problem code",
                              static_cast<double>(problem));
        return;
      }
      ++frames;
      latest = envelope.pin_frame();
      have_latest = true;
      if (csv) csv->Append(static_cast<double>(base::SteadyNowNs() - context.start_ns()) * 1e-9, latest);
    });
    const std::int64_t now = base::SteadyNowNs();
    health.SetCounter(frames_counter, frames);
    health.SetCounter(rejected_counter, rejected);
    context.Tick(now);
    if (options.heat_map && have_latest && now >= next_heat_map_ns) {
      next_heat_map_ns = now + heat_map_period_ns;
      std::cout << "\x1b[H\x1b[2J"
                << "frame " << latest.frame_index() << "\n"
                << RenderPinHeatMap(latest) << std::flush;
    }
  }
  if (csv) csv->Flush();
  context.log().info("played {} frames, rejected {}, dropped {} datagrams", frames, rejected,
                     context.messenger().received().TotalDropped());
  return 0;
}

}  // namespace
}  // namespace haptex::mock_pins

int main(int argc, char** argv) {
  auto options = std::make_shared<haptex::mock_pins::Options>();
  return haptex::services::RunService(
      argc, argv, "mock_pins", "Stand-in for the 6 x 4 vibrotactile pin displays",
      [options](CLI::App& app) {
        app.add_option("--log-csv", options->log_csv, "record every frame played to this CSV");
        app.add_flag("--heat-map", options->heat_map, "print a live 6 x 4 heat map per finger");
        app.add_option("--heat-map-hz", options->heat_map_hz, "heat map refresh rate")->check(CLI::Range(0.5, 60.0));
      },
      [options](haptex::services::ServiceContext& context) { return haptex::mock_pins::Run(context, *options); });
}
