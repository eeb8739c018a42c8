#pragma once
// Where a run's session key comes from (scene field session_key).

#include <string>

#include "haptex/v1/scene.pb.h"
#include "libs/net/session_key.h"

namespace haptex::scene {

/// hex: parsed; env: read from the variable; file: read from the file; generate or unset: a fresh
/// key. Throws std::invalid_argument when the key text is malformed and std::runtime_error when
/// the source cannot be read, each saying which source failed and why.
net::SessionKey ResolveSessionKey(const v1::SessionKey& source);

/// For processes started by hand or by the launcher: `key_file` when given, else the environment
/// variable HAPTEX_SESSION_KEY. Throws std::invalid_argument saying how to provide a key when
/// neither has one, or when the key is malformed.
net::SessionKey LoadSessionKey(const std::string& key_file);

}  // namespace haptex::scene
