// Every numeric flag of every `haptex` subcommand refuses NaN and infinities with exit code 2 and
// a message naming the value (CLI11's Range alone let `--ready-timeout nan` through). The flags are
// read from each subcommand's --help, so a flag added later is covered too.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "tests/support/numeric_flags.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex {
namespace {

using ::testing::HasSubstr;

using Result = haptex::testing::Finished;

Result Haptex(std::vector<std::string> args) {
  args.insert(args.begin(), testing::BuildDir() + "/cli/haptex");
  return testing::RunToEnd(std::move(args));
}

std::string Scene() { return testing::SourceDir() + "/launch/scenes/hanging.textproto"; }

// Each subcommand with what it needs besides the flag under test (positionals, required options).
std::vector<std::vector<std::string>> Subcommands() {
  return {{"launch", Scene(), "--dry-run"},
          {"sim", Scene()},
          {"netcheck", "serve", "--bind", "127.0.0.1:0"},
          {"netcheck", "probe", "--to", "127.0.0.1:9"},
          {"relay", "--listen", "127.0.0.1:0", "--to", "127.0.0.1:9"},
          {"fabric", "show", "wang2011_black_denim_11oz"},
          {"fabric", "list"},
          {"tactile", "build", "wang2011_black_denim_11oz"},
          {"trace", "export", "/no/such/run", "--csv"},
          {"view", "/no/such/run", "--seconds", "1"},
          {"scene", "check", Scene()},
          {"key", "generate"}};
}

TEST(HaptexFlagsTest, EverySubcommandIsListedHere) {
  const Result help = Haptex({"--help"});
  std::set<std::string> listed;
  for (const auto& args : Subcommands()) listed.insert(args[0]);
  const std::regex subcommand(R"(\n  ([a-z]+) {2,})");
  const std::string text = help.out.substr(help.out.find("Subcommands:"));
  int found = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), subcommand); it != std::sregex_iterator(); ++it) {
    EXPECT_TRUE(listed.count((*it)[1])) << "add `haptex " << (*it)[1] << "` to Subcommands()";
    ++found;
  }
  EXPECT_GE(found, 9);
}

TEST(HaptexFlagsTest, EveryNumericFlagRefusesNanAndInfinity) {
  int flags = 0;
  for (const auto& base : Subcommands()) {
    std::vector<std::string> help_args(base.begin(), base.end());
    help_args.push_back("--help");
    const Result help = Haptex(help_args);
    for (const std::string& flag : testing::NumericFlags(help.out)) {
      for (const std::string value : {"nan", "inf", "-inf"}) {
        std::vector<std::string> args = base;
        args.push_back(flag + "=" + value);
        const Result r = Haptex(args);
        EXPECT_EQ(r.code, 2) << base[0] << " " << flag << "=" << value << "\n" << r.err;
        EXPECT_THAT(r.err, HasSubstr(flag + ": ")) << flag << "=" << value;
        EXPECT_THAT(r.err, HasSubstr(value)) << flag << "=" << value;
      }
      ++flags;
    }
  }
  EXPECT_GE(flags, 15) << "the --help parsing found the flags";
}

TEST(HaptexFlagsTest, LaunchTimesRefuseNan) {
  for (const std::string flag : {"--ready-timeout", "--silent-after", "--duration"}) {
    const Result r = Haptex({"launch", Scene(), "--dry-run", flag, "nan"});
    EXPECT_EQ(r.code, 2) << flag;
    EXPECT_THAT(r.err, HasSubstr(flag + ": 'nan' is not a finite number"));
  }
}

}  // namespace
}  // namespace haptex
