#include "libs/scene/session_key_source.h"

#include <cstddef>
#include <cstdlib>
#include <stdexcept>

#include "libs/scene/text_proto.h"

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
        // 64 hex digits and a line end; the cap refuses /dev/zero and the like before reading
        constexpr std::size_t kMaxKeyFileBytes = 4096;
        try {
          return net::SessionKey::FromHex(ReadTextFile(source.file(), kMaxKeyFileBytes));
        } catch (const TextProtoError& e) {
          throw std::runtime_error(e.issues().front().message);
        }
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
