#pragma once

namespace haptex::net {

/// Initialises libsodium once (thread-safe); aborts if the library cannot start.
void EnsureSodiumInitialised();

}  // namespace haptex::net
