#pragma once
// The one loop skeleton of every haptex service (ros2_control style): absolute deadlines
// (next += period; sleep until next), measured period, overruns counted and skipped, a fixed
// nominal dt handed to the physics.

#include <cstdint>
#include <stdexcept>
#include <string>

#include "libs/base/clock.h"
#include "libs/runtime/loop_stats.h"

namespace haptex::runtime {

/// What a tick is told about its timing.
struct TickInfo {
  std::uint64_t tick = 0;               // 0, 1, 2, ... (skipped cycles are not numbered)
  std::int64_t now_ns = 0;              // when the tick started (base::SteadyNowNs)
  std::int64_t deadline_ns = 0;         // when it was due
  std::int64_t measured_period_ns = 0;  // since the previous tick started (0 for the first)
  std::uint64_t skipped = 0;            // cycles skipped just before this tick
  double dt_s = 0.0;                    // the nominal period: use this as the physics step
};

class PeriodicLoop final {
 public:
  /// Throws std::invalid_argument unless 0 < rate_hz <= 100 kHz.
  PeriodicLoop(std::string name, double rate_hz);

  /// Calls tick(const TickInfo&) at each deadline until should_stop() is true (checked before
  /// every tick). Neither allocates nor logs.
  template <class Tick, class ShouldStop>
  void Run(Tick&& tick, ShouldStop&& should_stop) {
    std::int64_t next_ns = base::SteadyNowNs() + period_ns_;
    std::int64_t previous_start_ns = 0;
    while (!should_stop()) {
      SleepUntil(next_ns);
      TickInfo info;
      info.now_ns = base::SteadyNowNs();
      const std::int64_t late_ns = info.now_ns - next_ns;
      if (late_ns >= period_ns_) {
        // skip the cycles we missed rather than running them back to back
        info.skipped = static_cast<std::uint64_t>(late_ns / period_ns_);
        stats_.overruns += info.skipped;
        next_ns += static_cast<std::int64_t>(info.skipped) * period_ns_;
      }
      info.deadline_ns = next_ns;
      if (previous_start_ns != 0) {
        info.measured_period_ns = info.now_ns - previous_start_ns;
        stats_.period.Record(info.measured_period_ns);
      }
      previous_start_ns = info.now_ns;
      info.tick = stats_.ticks;
      info.dt_s = dt_s_;
      tick(static_cast<const TickInfo&>(info));
      stats_.compute.Record(base::SteadyNowNs() - info.now_ns);
      ++stats_.ticks;
      next_ns += period_ns_;
    }
  }

  const LoopStats& stats() const { return stats_; }
  std::int64_t period_ns() const { return period_ns_; }
  double dt_s() const { return dt_s_; }

 private:
  static void SleepUntil(std::int64_t deadline_ns);

  std::int64_t period_ns_;
  double dt_s_;
  LoopStats stats_;
};

}  // namespace haptex::runtime
