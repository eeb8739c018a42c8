#pragma once

#include <CLI/CLI.hpp>

namespace haptex::cli {

/// `haptex sim SCENE [--duration S] [--out DIR]`: the scene's fabric alone, offline, as fast as it
/// goes; writes particles.csv, mesh.obj and summary.json.
void AddSimCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::cli
