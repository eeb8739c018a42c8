#pragma once

#include <CLI/CLI.hpp>

namespace haptex::cli {

/// `haptex key generate [--out FILE]`: a fresh session key for runs across machines.
void AddKeyCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::cli
