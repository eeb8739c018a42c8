// Every numeric flag of every service (the shared ones of services/common and each service's own)
// refuses NaN and infinities with exit code 2 before the service starts. The flags are read from
// each binary's --help, so a flag added later is covered too.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/support/numeric_flags.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex {
namespace {

using ::testing::HasSubstr;

using Result = haptex::testing::Finished;

Result RunService(std::vector<std::string> args) { return testing::RunToEnd(std::move(args)); }

// Each service binary with its required options.
std::vector<std::vector<std::string>> Services() {
  const std::string bin = testing::BuildDir() + "/services/";
  return {{bin + "device_bridge/haptex-device-bridge"},
          {bin + "mock_grab/haptex-mock-grab", "--bridge", "127.0.0.1:9"},
          {bin + "global_sim/haptex-global-sim"},
          {bin + "local_contact/haptex-local-contact"},
          {bin + "tactile/haptex-tactile"},
          {bin + "mock_pins/haptex-mock-pins"}};
}

TEST(ServiceOptionsTest, RateNanIsExitCode2) {
  const Result r = RunService(
      {testing::BuildDir() + "/services/mock_grab/haptex-mock-grab", "--bridge", "127.0.0.1:9", "--rate", "nan"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("--rate: 'nan' is not a finite number"));
}

TEST(ServiceOptionsTest, EveryNumericFlagOfEveryServiceRefusesNanAndInfinity) {
  for (const auto& base : Services()) {
    std::vector<std::string> help_args = base;
    help_args.push_back("--help");
    const std::set<std::string> flags = testing::NumericFlags(RunService(help_args).out);
    EXPECT_TRUE(flags.count("--health-hz") && flags.count("--duration")) << base[0] << ": the shared flags";
    for (const std::string& flag : flags) {
      for (const std::string value : {"nan", "inf", "-inf"}) {
        std::vector<std::string> args = base;
        args.push_back(flag + "=" + value);
        const Result r = RunService(args);
        EXPECT_EQ(r.code, 2) << base[0] << " " << flag << "=" << value << "\n" << r.err;
        EXPECT_THAT(r.err, HasSubstr(flag + ": ")) << base[0] << " " << flag << "=" << value;
      }
    }
  }
}

}  // namespace
}  // namespace haptex
