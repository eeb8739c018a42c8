#pragma once

#include <CLI/CLI.hpp>

namespace haptex::cli {

/// `haptex relay`: a user-space network impairment relay (docs/relay.md).
void AddRelayCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::cli
