#pragma once
// Clean shutdown on SIGINT/SIGTERM: the handler only sets a flag that loops poll.

namespace haptex::runtime {

/// Installs handlers for SIGINT and SIGTERM (idempotent).
void InstallShutdownHandlers();
/// True once a signal arrived or RequestShutdown() was called.
bool ShutdownRequested();
/// Same effect as a signal (a Control SHUTDOWN message, a fatal input error).
void RequestShutdown();
/// The signal number that asked for shutdown, or 0.
int ShutdownSignalNumber();

}  // namespace haptex::runtime
