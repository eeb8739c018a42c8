#pragma once
// The session key for commands run by hand: --key-file, else $HAPTEX_SESSION_KEY.

#include <string>

#include "libs/net/session_key.h"

namespace haptex::cli {

/// Throws std::invalid_argument explaining how to provide a key when neither source has one.
net::SessionKey LoadCliSessionKey(const std::string& key_file);

}  // namespace haptex::cli
