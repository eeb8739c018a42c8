#pragma once

#include <CLI/CLI.hpp>

namespace haptex::cli {

/// `haptex netcheck serve|probe`: measures a link the way a haptic session would use it.
void AddNetcheckCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::cli
