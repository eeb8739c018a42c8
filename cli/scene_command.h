#pragma once

#include <CLI/CLI.hpp>

namespace haptex::cli {

/// `haptex scene check FILE...`: validates scenes (and their fabrics) without running them.
void AddSceneCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::cli
