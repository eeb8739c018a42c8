#pragma once

#include <CLI/CLI.hpp>

namespace haptex::cli {

/// `haptex fabric list` and `haptex fabric show NAME [--plot FILE.png]`.
void AddFabricCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::cli
