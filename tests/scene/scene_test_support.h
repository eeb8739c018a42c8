#pragma once

#include <cstdlib>
#include <string>

namespace haptex::scene::testing {

/// tests/scene/testdata, found through HAPTEX_SOURCE_DIR (set by ctest).
inline std::string TestDataDir() {
  const char* root = std::getenv("HAPTEX_SOURCE_DIR");
  return std::string(root ? root : ".") + "/tests/scene/testdata";
}

}  // namespace haptex::scene::testing
