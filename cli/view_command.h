#pragma once

#include <CLI/CLI.hpp>

namespace haptex::cli {

/// `haptex view RUN_FOLDER`: replays a finished run in the viewer's page (docs/viewer.md).
void AddViewCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::cli
