#pragma once
// The numeric flags a CLI11 program declares, read from its --help (type FLOAT, INT or UINT), so
// that a test covers every flag, including ones added later.

#include <regex>
#include <set>
#include <string>

namespace haptex::testing {

/// "--name" of every option whose help shows a numeric type.
inline std::set<std::string> NumericFlags(const std::string& help) {
  std::set<std::string> flags;
  const std::regex option(R"((--[a-z0-9][a-z0-9-]*) (FLOAT|INT|UINT)\b)");
  for (auto it = std::sregex_iterator(help.begin(), help.end(), option); it != std::sregex_iterator(); ++it) {
    flags.insert((*it)[1]);
  }
  return flags;
}

}  // namespace haptex::testing
