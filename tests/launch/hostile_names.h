#pragma once
// Scene names an attacker would write: a newline and a gnuplot shell escape, quotes, path climbs,
// control characters, bytes that are not UTF-8, and a megabyte.

#include <string>
#include <vector>

namespace haptex::launch::testing {

/// `marker` is the absolute path a successful injection would create.
inline std::vector<std::string> HostileNames(const std::string& marker) {
  return {"x\n!touch " + marker + "\n",
          "x'\n!touch " + marker + "\n'",
          "it's \"quoted\" `touch " + marker + "` $(touch " + marker + ") @x",
          "../../x",
          "..",
          ".",
          "/etc/x",
          "a/../../../b",
          std::string("\x01\x1b[31mred\r\t\x7f", 12),
          "\xff\xfe\xc3(\xa0\xa1",
          "",
          std::string(1 << 20, 'a'),
          std::string(1 << 20, '/')};
}

}  // namespace haptex::launch::testing
