#include "libs/scene/session_key_source.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace haptex::scene {

net::SessionKey ResolveSessionKey(const v1::SessionKey& source) {
  try {
    switch (source.source_case()) {
      case v1::SessionKey::kHex:
        return net::SessionKey::FromHex(source.hex());
      case v1::SessionKey::kEnv: {
        const char* value = std::getenv(source.env().c_str());
        if (value == nullptr) throw std::runtime_error("environment variable is not set");
        return net::SessionKey::FromHex(value);
      }
      case v1::SessionKey::kFile: {
        std::ifstream in(source.file());
        if (!in) throw std::runtime_error("cannot open the file");
        std::stringstream text;
        text << in.rdbuf();
        return net::SessionKey::FromHex(text.str());
      }
      default:
        return net::SessionKey::Generate();
    }
  } catch (const std::exception& e) {
    const std::string where = source.has_env()    ? "environment variable " + source.env()
                              : source.has_file() ? "file " + source.file()
                                                  : "session_key.hex";
    throw std::runtime_error("session key from " + where + ": " + e.what());
  }
}

}  // namespace haptex::scene
