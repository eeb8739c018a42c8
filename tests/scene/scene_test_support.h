#pragma once

#include <string>

#include "tests/support/test_paths.h"

namespace haptex::scene::testing {

inline std::string TestDataDir() { return haptex::testing::SourceDir() + "/tests/scene/testdata"; }

}  // namespace haptex::scene::testing
