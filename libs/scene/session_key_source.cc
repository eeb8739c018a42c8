#include "libs/scene/session_key_source.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace haptex::scene {
namespace {

std::string DescribeSource(const v1::SessionKey& source) {
  return "session key from " + (source.has_env()    ? "environment variable " + source.env()
                                : source.has_file() ? "file " + source.file()
                                                    : std::string("session_key.hex"));
}

}  // namespace

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
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(DescribeSource(source) + ": " + e.what());
  } catch (const std::exception& e) {
    throw std::runtime_error(DescribeSource(source) + ": " + e.what());
  }
}

net::SessionKey LoadSessionKey(const std::string& key_file) {
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
  try {
    return ResolveSessionKey(source);
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());  // an unreadable key file is bad input too
  }
}

}  // namespace haptex::scene
