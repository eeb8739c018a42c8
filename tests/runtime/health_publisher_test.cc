#include "libs/runtime/health_publisher.h"

#include <gtest/gtest.h>

#include <optional>
#include <thread>
#include <vector>

#include "libs/base/clock.h"
#include "libs/runtime/periodic_loop.h"
#include "tests/support/allocation_counter.h"

namespace haptex::runtime {
namespace {

constexpr std::uint64_t kSession = 5;

net::MessengerConfig Config(const char* name) {
  net::MessengerConfig config;
  config.identity = {name, 0, kSession};
  return config;
}

TEST(HealthPublisherTest, RejectsBadRates) {
  const auto key = net::SessionKey::Generate();
  net::Messenger m(key, Config("svc"));
  HealthReporter reporter("svc");
  EXPECT_THROW(HealthPublisher(&reporter, &m, 0, 0.0, 0), std::invalid_argument);
  EXPECT_THROW(HealthPublisher(&reporter, &m, 0, 5000.0, 0), std::invalid_argument);
}

// Due says whether MaybePublish would send, so a service refreshes what it reports only then.
TEST(HealthPublisherTest, DueExactlyWhenItWouldSend) {
  const auto key = net::SessionKey::Generate();
  net::Messenger launcher(key, Config("launcher"));
  net::Messenger service(key, Config("svc"));
  HealthReporter reporter("svc");
  HealthPublisher publisher(&reporter, &service, service.AddPeer("launcher", launcher.local_endpoint()), 10.0, 0);
  EXPECT_TRUE(publisher.Due(0));
  EXPECT_TRUE(publisher.MaybePublish(0));
  EXPECT_FALSE(publisher.Due(99'999'999));
  EXPECT_FALSE(publisher.MaybePublish(99'999'999));
  EXPECT_TRUE(publisher.Due(100'000'000));
  EXPECT_TRUE(publisher.MaybePublish(100'000'000));
}

// A loop publishes its own Health over real UDP; the launcher side receives it in order.
TEST(HealthPublisherTest, LoopPublishesItsStatisticsAtTheHealthRate) {
  const auto key = net::SessionKey::Generate();
  net::Messenger launcher(key, Config("launcher"));
  net::Messenger service(key, Config("local_contact"));
  const auto to_launcher = service.AddPeer("launcher", launcher.local_endpoint());

  PeriodicLoop loop("haptic", 1000.0);
  HealthReporter reporter("local_contact");
  reporter.AddLoop(&loop.stats());
  const auto ticks_counter = reporter.AddCounter("ticks_seen");
  reporter.SetState(v1::Health::STATE_READY);
  const std::int64_t start = base::SteadyNowNs();
  HealthPublisher publisher(&reporter, &service, to_launcher, 50.0, start);

  std::uint64_t ticks = 0;
  std::int64_t allocations_in_steady_state = 0;
  std::optional<testing::AllocationCounter> counter;
  const std::int64_t run_start_ns = base::SteadyNowNs();
  loop.Run(
      [&](const TickInfo& info) {
        ++ticks;
        reporter.SetCounter(ticks_counter, ticks);
        if (ticks == 50) counter.emplace();  // after warm-up
        publisher.MaybePublish(info.now_ns);
        if (ticks == 250) {
          allocations_in_steady_state = counter->count();
        }
      },
      [&] { return ticks >= 300; });
  const double run_s = static_cast<double>(base::SteadyNowNs() - run_start_ns) * 1e-9;

  std::vector<v1::Health> received;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (received.size() < publisher.published() && std::chrono::steady_clock::now() < until) {
    launcher.WaitReadable(std::chrono::milliseconds(10));
    launcher.Drain([&](const v1::Envelope& e, const net::Messenger::Endpoint&) {
      ASSERT_EQ(e.body_case(), v1::Envelope::kHealth);
      received.push_back(e.health());
    });
  }
  // ~300 ms at 50 Hz: about 15; a loaded machine stretches the run (skipped cycles), but the
  // cadence never bursts: at most one message per 20 ms of the run, plus the first
  ASSERT_GE(publisher.published(), 3u);
  EXPECT_LE(static_cast<double>(publisher.published()), run_s * 50.0 + 2.0);
  ASSERT_EQ(received.size(), publisher.published());
  for (std::size_t i = 1; i < received.size(); ++i) {
    EXPECT_GT(received[i].uptime_s(), received[i - 1].uptime_s());
    EXPECT_GT(received[i].loops(0).ticks(), received[i - 1].loops(0).ticks());
  }
  const v1::Health& last = received.back();
  EXPECT_EQ(last.service(), "local_contact");
  EXPECT_EQ(last.state(), v1::Health::STATE_READY);
  EXPECT_EQ(last.loops(0).name(), "haptic");
  EXPECT_DOUBLE_EQ(last.loops(0).target_rate_hz(), 1000.0);
  EXPECT_GT(last.loops(0).period_p50_us(), 0.0);
  EXPECT_EQ(last.counters(0).name(), "ticks_seen");
  if (testing::AllocationCountingSupported()) {
    EXPECT_EQ(allocations_in_steady_state, 0);
  }
}

}  // namespace
}  // namespace haptex::runtime
