#include "libs/runtime/rt_options.h"

#include <gtest/gtest.h>
#include <sched.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <sstream>

namespace haptex::runtime {
namespace {

TEST(RtOptionsTest, RefusedRequestsWarnAndContinue) {
  std::ostringstream out;
  spdlog::logger logger("rt_test", std::make_shared<spdlog::sinks::ostream_sink_mt>(out));
  logger.set_pattern("%l %v");
  RtOptions options;
  options.cpus = {4096};  // no such CPU
  EXPECT_EQ(ApplyRtOptions(options, logger), 1);
  EXPECT_NE(out.str().find("warning rt: CPU 4096 does not exist"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("continuing without it"), std::string::npos);
}

TEST(RtOptionsTest, GrantedRequestsAreLoggedAsInfo) {
  std::ostringstream out;
  spdlog::logger logger("rt_test", std::make_shared<spdlog::sinks::ostream_sink_mt>(out));
  logger.set_pattern("%l %v");
  RtOptions options;
  options.cpus = {0};
  EXPECT_EQ(ApplyRtOptions(options, logger), 0);
  EXPECT_NE(out.str().find("info rt: pinned to CPU 0"), std::string::npos) << out.str();
  cpu_set_t all;
  CPU_ZERO(&all);
  for (int i = 0; i < CPU_SETSIZE; ++i) CPU_SET(i, &all);
  sched_setaffinity(0, sizeof(all), &all);
}

TEST(RtOptionsTest, NothingRequestedDoesNothing) {
  std::ostringstream out;
  spdlog::logger logger("rt_test", std::make_shared<spdlog::sinks::ostream_sink_mt>(out));
  EXPECT_EQ(ApplyRtOptions(RtOptions{}, logger), 0);
  EXPECT_EQ(out.str(), "");
}

}  // namespace
}  // namespace haptex::runtime
