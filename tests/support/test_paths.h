#pragma once
// Where a test finds the source tree (test data) and the build tree (executables). haptex_cc_test
// compiles both paths in; HAPTEX_SOURCE_DIR / HAPTEX_BUILD_DIR override them.

#include <cstdlib>
#include <string>

namespace haptex::testing {

inline std::string SourceDir() {
  const char* env = std::getenv("HAPTEX_SOURCE_DIR");
  return env && *env ? env : HAPTEX_TEST_SOURCE_DIR;
}

inline std::string BuildDir() {
  const char* env = std::getenv("HAPTEX_BUILD_DIR");
  return env && *env ? env : HAPTEX_TEST_BUILD_DIR;
}

}  // namespace haptex::testing
