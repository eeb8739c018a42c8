#pragma once

#include <CLI/CLI.hpp>

namespace haptex::launch {

/// `haptex launch SCENE [--duration S] [--out DIR] [--host NAME] ...`: starts what the scene needs,
/// supervises it, stops it safely, and leaves a run folder (docs/launch.md).
void AddLaunchCommand(CLI::App& app, int* exit_code);

}  // namespace haptex::launch
