#pragma once
// The mock GRAB controller's force log (haptex-mock-grab --force-log): per controller tick its
// CLOCK_MONOTONIC time and the commanded and applied force of each finger.

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/subprocess.h"

namespace haptex::testing {

/// One row: the time and the commanded force magnitude per finger.
struct ForceRow {
  double t_ns = 0.0, thumb_N = 0.0, index_N = 0.0;
};

inline std::vector<ForceRow> MockForceRows(const std::string& csv_path) {
  std::vector<ForceRow> rows;
  std::istringstream in(ReadFileOrEmpty(csv_path));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) v.push_back(std::stod(cell));
    if (v.size() != 15) continue;  // a row cut short by a kill
    rows.push_back({v[0], std::hypot(v[1], v[2], v[3]), std::hypot(v[7], v[8], v[9])});
  }
  return rows;
}

}  // namespace haptex::testing
