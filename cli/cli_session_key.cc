#include "cli/cli_session_key.h"

#include <cstdlib>
#include <stdexcept>

#include "libs/scene/session_key_source.h"

namespace haptex::cli {

net::SessionKey LoadCliSessionKey(const std::string& key_file) {
  v1::SessionKey source;
  if (!key_file.empty()) {
    source.set_file(key_file);
  } else if (const char* env = std::getenv("HAPTEX_SESSION_KEY"); env != nullptr && *env != '\0') {
    source.set_env("HAPTEX_SESSION_KEY");
  } else {
    throw std::invalid_argument(
        "no session key: pass --key-file FILE or set HAPTEX_SESSION_KEY to 64 hex digits "
        "(make one with `haptex key generate`); both ends need the same key");
  }
  return scene::ResolveSessionKey(source);
}

}  // namespace haptex::cli
