#include "libs/runtime/periodic_loop.h"

#include <cerrno>
#include <cmath>
#include <ctime>

namespace haptex::runtime {

PeriodicLoop::PeriodicLoop(std::string name, double rate_hz) {
  if (!(rate_hz > 0.0) || rate_hz > 100e3 || !std::isfinite(rate_hz)) {
    throw std::invalid_argument("loop '" + name + "': rate must be in (0, 100000] Hz, got " + std::to_string(rate_hz));
  }
  period_ns_ = static_cast<std::int64_t>(std::llround(1e9 / rate_hz));
  dt_s_ = static_cast<double>(period_ns_) * 1e-9;
  stats_.name = std::move(name);
  stats_.target_rate_hz = rate_hz;
}

void PeriodicLoop::SleepUntil(std::int64_t deadline_ns) {
  // steady_clock is CLOCK_MONOTONIC on Linux, so the absolute deadline is on the same clock.
  timespec deadline{};
  deadline.tv_sec = static_cast<time_t>(deadline_ns / 1000000000);
  deadline.tv_nsec = static_cast<long>(deadline_ns % 1000000000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
}

}  // namespace haptex::runtime
