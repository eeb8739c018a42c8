#pragma once

#include <CLI/CLI.hpp>

namespace haptex::cli {

/// `haptex tactile build FABRIC [--out FILE.tile] [--png PREFIX] [surface values]`: the fabric's
/// virtual tactile surface and its periodic tile (pre-processing for haptex-tactile).
void AddTactileCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::cli
