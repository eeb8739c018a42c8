#pragma once
// Turns recordings into CSV, one file per body type (health.csv, force_model.csv,
// touch_trace.csv, finger_states.csv, pin_frame.csv, control.csv, ...). Times are seconds from
// the earliest message of the run (one machine's steady clock).

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "launch/recording.h"

namespace haptex::launch {

/// Writes the CSV files into `out_dir` (created). Returns rows written per file name; a body type
/// that was never recorded gets no file. Throws std::runtime_error when a file cannot be written.
std::map<std::string, std::size_t> ExportCsv(const std::vector<Recording>& recordings, const std::string& out_dir);

/// Name of a finger for CSV and plots ("thumb", "index").
std::string FingerName(int finger);

}  // namespace haptex::launch
