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

}  // namespace haptex::scene
