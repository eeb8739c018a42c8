#pragma once
// The mock GRAB controller's force log (haptex-mock-grab --force-log), as the tests read it: per
// controller tick its CLOCK_MONOTONIC time and the commanded force magnitude of each finger.

#include <string>
#include <vector>

#include "launch/force_log_reader.h"

namespace haptex::testing {

/// One row: the time and the commanded force magnitude per finger.
struct ForceRow {
  double t_ns = 0.0, thumb_N = 0.0, index_N = 0.0;
};

inline std::vector<ForceRow> MockForceRows(const std::string& csv_path) {
  std::vector<ForceRow> rows;
  for (const device::ForceLogRow& r : launch::ReadForceLogRows(csv_path)) {
    rows.push_back({static_cast<double>(r.time_ns), r.CommandedNormN(0), r.CommandedNormN(1)});
  }
  return rows;
}

/// Milliseconds the host was paused between from_ns and until_ns, as gaps in the mock's 5 kHz rows
/// show (a gap of ten ticks or more, less the tick it would have had anyway). A pause of the whole
/// host stops every watchdog's clock-reading too, so a watchdog's bound holds in the time the
/// machine ran: such a test subtracts this from the wall-clock time it measured.
inline double HostPausedMs(const std::vector<ForceRow>& rows, double from_ns, double until_ns) {
  constexpr double kTick_ns = 2e5, kPauseGap_ns = 2e6;
  double paused_ns = 0.0, previous_ns = from_ns;
  for (const ForceRow& r : rows) {
    if (r.t_ns < from_ns) continue;
    if (r.t_ns > until_ns) break;
    if (r.t_ns - previous_ns >= kPauseGap_ns) paused_ns += r.t_ns - previous_ns - kTick_ns;
    previous_ns = r.t_ns;
  }
  return paused_ns * 1e-6;
}

}  // namespace haptex::testing
