#pragma once

#include <CLI/CLI.hpp>

namespace haptex::cli {

/// `haptex trace export RUN --csv [--out DIR]`: a run's recordings as CSV, one file per body type.
void AddTraceCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::cli
