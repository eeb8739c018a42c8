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
  cpu_set_t original;
  ASSERT_EQ(sched_getaffinity(0, sizeof(original), &original), 0);
  int cpu = 0;
  while (cpu < CPU_SETSIZE && !CPU_ISSET(cpu, &original)) ++cpu;
  RtOptions options;
  options.cpus = {cpu};
  EXPECT_EQ(ApplyRtOptions(options, logger), 0);
  EXPECT_NE(out.str().find("info rt: pinned to CPU " + std::to_string(cpu)), std::string::npos) << out.str();
  sched_setaffinity(0, sizeof(original), &original);
}

TEST(RtOptionsTest, NothingRequestedDoesNothing) {
  std::ostringstream out;
  spdlog::logger logger("rt_test", std::make_shared<spdlog::sinks::ostream_sink_mt>(out));
  EXPECT_EQ(ApplyRtOptions(RtOptions{}, logger), 0);
  EXPECT_EQ(out.str(), "");
}

}  // namespace
}  // namespace haptex::runtime
