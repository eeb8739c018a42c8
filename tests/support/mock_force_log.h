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

}  // namespace haptex::testing
