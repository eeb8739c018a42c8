#include "libs/netsim/impairment_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "libs/netsim/release_queue.h"
#include "tests/support/allocation_counter.h"

namespace haptex::netsim {
namespace {

constexpr std::int64_t kMs = 1'000'000;

// Binomial bound: |count - n p| within 5 standard deviations (a false failure about once in
// 3.5 million runs).
double BinomialSlack(double n, double p) { return 5.0 * std::sqrt(n * p * (1.0 - p)) + 1.0; }

struct Delivered {
  std::uint64_t sequence;
  std::int64_t arrival_ns;
  std::int64_t release_ns;
};

// Offers `count` datagrams `spacing_ns` apart (size from `size_of`), releasing every copy when
// its time comes as the relay does, and reports each delivery to the model. Returns the copies in
// delivery order.
template <typename SizeOf>
std::vector<Delivered> Simulate(ImpairmentModel* model, int count, std::int64_t spacing_ns, SizeOf size_of) {
  ReleaseQueue queue(static_cast<std::size_t>(2 * count));
  std::vector<Delivered> delivered;
  const auto deliver_until = [&](std::int64_t now_ns) {
    while (!queue.empty() && queue.Top().release_ns <= now_ns) {
      const ScheduledCopy copy = queue.Pop();
      model->OnDelivered(copy.sequence, copy.arrival_ns, copy.release_ns);
      delivered.push_back({copy.sequence, copy.arrival_ns, copy.release_ns});
    }
  };
  for (int i = 0; i < count; ++i) {
    const std::int64_t now_ns = i * spacing_ns;
    deliver_until(now_ns);
    const Decision decision = model->Decide(now_ns, size_of(i));
    for (int c = 0; c < decision.copies; ++c) {
      queue.Push({decision.release_ns[static_cast<std::size_t>(c)], decision.arrival_ns, decision.sequence, 0, 0});
    }
  }
  deliver_until(std::numeric_limits<std::int64_t>::max());
  return delivered;
}

std::vector<Delivered> Simulate(ImpairmentModel* model, int count, std::int64_t spacing_ns) {
  return Simulate(model, count, spacing_ns, [](int) { return std::size_t{200}; });
}

// Reordered copies counted the slow way: delivered after a datagram that arrived later.
std::uint64_t CountReordered(const std::vector<Delivered>& delivered) {
  std::uint64_t reordered = 0, highest = 0;
  bool any = false;
  for (const Delivered& d : delivered) {
    if (any && d.sequence < highest) ++reordered;
    highest = std::max(highest, d.sequence);
    any = true;
  }
  return reordered;
}

void ExpectAccountsBalance(const ImpairmentStats& stats) {
  EXPECT_EQ(stats.in_flight(), 0u);
  EXPECT_EQ(stats.forwarded + stats.dropped.Total(), stats.received + stats.duplicated);
}

// A dead link: nothing gets through for outage_s from outage_after_s after the first datagram,
// everything before and after does; the spell's start is reported on the arrival clock.
TEST(ImpairmentModelTest, AnOutageDropsEverythingInItsWindowAndNothingElse) {
  ImpairmentConfig config;
  config.outage_after_s = 0.1;
  config.outage_s = 0.05;
  ImpairmentModel dut(config, 1);
  constexpr std::int64_t kFirst_ns = 7 * kMs;
  for (int i = 0; i < 300; ++i) {
    const std::int64_t arrival_ns = kFirst_ns + i * kMs;
    const bool dead = arrival_ns >= kFirst_ns + 100 * kMs && arrival_ns < kFirst_ns + 150 * kMs;
    EXPECT_EQ(dut.Decide(arrival_ns, 100).copies, dead ? 0 : 1) << "datagram " << i;
  }
  EXPECT_EQ(dut.stats().dropped.Get(DropCause::kOutage), 50u);
  EXPECT_EQ(dut.stats().dropped.Total(), 50u);
  EXPECT_EQ(dut.stats().outage_from_ns, kFirst_ns + 100 * kMs);
}

TEST(ImpairmentModelTest, WithoutImpairmentsEveryDatagramLeavesAtOnceInOrder) {
  ImpairmentModel dut(ImpairmentConfig{}, 1);
  for (int i = 0; i < 1000; ++i) {
    const Decision decision = dut.Decide(i * kMs, 100);
    ASSERT_EQ(decision.copies, 1);
    EXPECT_EQ(decision.sequence, static_cast<std::uint64_t>(i));
    EXPECT_EQ(decision.release_ns[0], i * kMs);
  }
  EXPECT_EQ(dut.stats().received, 1000u);
  EXPECT_EQ(dut.stats().dropped.Total(), 0u);
}

TEST(ImpairmentModelTest, ConstantDelayIsAddedExactly) {
  ImpairmentConfig config;
  config.delay_ms = 25.5;
  ImpairmentModel dut(config, 1);
  const auto delivered = Simulate(&dut, 1000, kMs);
  ASSERT_EQ(delivered.size(), 1000u);
  for (const Delivered& d : delivered) ASSERT_EQ(d.release_ns - d.arrival_ns, 25'500'000);
  EXPECT_EQ(dut.stats().delay.max_ns(), 25'500'000);
  EXPECT_NEAR(dut.stats().delay.Quantile_ns(0.5), 25.5e6, 0.01 * 25.5e6);
  ExpectAccountsBalance(dut.stats());
}

TEST(ImpairmentModelTest, LossFractionWithinBinomialBounds) {
  constexpr int kN = 100000;
  for (const double loss : {0.001, 0.05, 0.3}) {
    ImpairmentConfig config;
    config.loss = loss;
    ImpairmentModel dut(config, 11);
    Simulate(&dut, kN, kMs);
    const auto lost = static_cast<double>(dut.stats().dropped.Get(DropCause::kLoss));
    EXPECT_NEAR(lost, kN * loss, BinomialSlack(kN, loss)) << "loss " << loss;
    EXPECT_EQ(dut.stats().dropped.Total(), dut.stats().dropped.Get(DropCause::kLoss));
    ExpectAccountsBalance(dut.stats());
  }
}

TEST(ImpairmentModelTest, SameSeedSameDecisionsOtherSeedOthers) {
  ImpairmentConfig config;
  config.delay_ms = 10;
  config.jitter_ms = 3;
  config.jitter_distribution = JitterDistribution::kNormal;
  config.loss = 0.1;
  config.burst = {.p_good_to_bad = 0.02, .p_bad_to_good = 0.3};
  config.duplicate = 0.05;
  config.reorder = 0.05;
  config.rate_kbps = 5000;
  const auto decisions = [&](std::uint64_t seed) {
    ImpairmentModel dut(config, seed);
    std::vector<std::int64_t> out;
    for (int i = 0; i < 20000; ++i) {
      const Decision d = dut.Decide(i * kMs / 2, 100 + static_cast<std::size_t>(i % 900));
      out.push_back(d.copies);
      for (int c = 0; c < d.copies; ++c) out.push_back(d.release_ns[static_cast<std::size_t>(c)]);
    }
    return out;
  };
  EXPECT_EQ(decisions(5), decisions(5));
  EXPECT_NE(decisions(5), decisions(6));
}

TEST(ImpairmentModelTest, OneKnobDoesNotChangeTheOthersDecisions) {
  // which datagrams are lost depends on the seed only, not on jitter, duplication or reordering
  const auto lost = [](bool other_knobs) {
    ImpairmentConfig config;
    config.loss = 0.2;
    if (other_knobs) {
      config.jitter_ms = 5;
      config.duplicate = 0.3;
      config.reorder = 0.3;
    }
    ImpairmentModel dut(config, 3);
    std::vector<bool> out;
    for (int i = 0; i < 5000; ++i) out.push_back(dut.Decide(i * kMs, 100).copies == 0);
    return out;
  };
  EXPECT_EQ(lost(false), lost(true));
}

TEST(ImpairmentModelTest, GilbertElliottMatchesTheStationaryLossRateAndMeanBurstLength) {
  constexpr int kN = 200000;
  constexpr double p = 0.01, r = 0.25;
  ImpairmentConfig config;
  config.burst = {.p_good_to_bad = p, .p_bad_to_good = r};
  ImpairmentModel dut(config, 21);
  std::vector<int> bursts;
  int run = 0;
  for (int i = 0; i < kN; ++i) {
    if (dut.Decide(i * kMs, 100).copies == 0) {
      ++run;
    } else if (run > 0) {
      bursts.push_back(run);
      run = 0;
    }
  }
  // stationary: P(bad) = p / (p + r), every datagram in the bad state lost
  const double pi_bad = p / (p + r);
  // a Markov chain's time average varies more than a binomial: variance
  // pi_bad (1 - pi_bad) (1 + lambda) / (1 - lambda) / N with lambda = 1 - p - r
  const double lambda = 1.0 - p - r;
  const double sd = std::sqrt(pi_bad * (1 - pi_bad) * (1 + lambda) / (1 - lambda) / kN);
  const double loss_rate = static_cast<double>(dut.stats().dropped.Get(DropCause::kBurstLoss)) / kN;
  EXPECT_NEAR(loss_rate, pi_bad, 5 * sd);
  EXPECT_EQ(dut.stats().dropped.Get(DropCause::kLoss), 0u);
  // bursts are geometric with mean 1 / r and sd sqrt(1 - r) / r
  ASSERT_GT(bursts.size(), 1000u);
  double sum = 0;
  for (const int b : bursts) sum += b;
  const double mean = sum / static_cast<double>(bursts.size());
  EXPECT_NEAR(mean, 1.0 / r, 5 * std::sqrt(1 - r) / r / std::sqrt(static_cast<double>(bursts.size())));
}

TEST(ImpairmentModelTest, GilbertElliottWithLossInBothStates) {
  constexpr int kN = 200000;
  ImpairmentConfig config;
  config.burst = {.p_good_to_bad = 0.05, .p_bad_to_good = 0.2, .loss_good = 0.01, .loss_bad = 0.6};
  ImpairmentModel dut(config, 8);
  Simulate(&dut, kN, kMs);
  const double pi_bad = 0.05 / 0.25;
  const double expected = (1 - pi_bad) * 0.01 + pi_bad * 0.6;
  const double loss_rate = static_cast<double>(dut.stats().dropped.Get(DropCause::kBurstLoss)) / kN;
  // generous: the state's autocorrelation widens the binomial spread (lambda = 0.75: x7)
  EXPECT_NEAR(loss_rate, expected, 5 * std::sqrt(7.0 * expected * (1 - expected) / kN));
  ExpectAccountsBalance(dut.stats());
}

struct Moments {
  double mean = 0, sd = 0, min = 0, max = 0;
};

Moments JitterMoments(JitterDistribution distribution, double delay_ms, double jitter_ms, int n) {
  ImpairmentConfig config;
  config.delay_ms = delay_ms;
  config.jitter_ms = jitter_ms;
  config.jitter_distribution = distribution;
  ImpairmentModel dut(config, 99);
  double sum = 0, sum_sq = 0;
  Moments m{0, 0, 1e300, -1e300};
  for (int i = 0; i < n; ++i) {
    const Decision d = dut.Decide(i * kMs, 100);
    const double jitter = static_cast<double>(d.release_ns[0] - d.arrival_ns) / kMs - delay_ms;
    sum += jitter;
    sum_sq += jitter * jitter;
    m.min = std::min(m.min, jitter);
    m.max = std::max(m.max, jitter);
  }
  m.mean = sum / n;
  m.sd = std::sqrt(sum_sq / n - m.mean * m.mean);
  return m;
}

TEST(ImpairmentModelTest, UniformJitterHasTheRightMeanSpreadAndBounds) {
  constexpr int kN = 100000;
  const Moments m = JitterMoments(JitterDistribution::kUniform, 50, 6, kN);
  const double sd = 6 / std::sqrt(3.0);
  EXPECT_NEAR(m.mean, 0.0, 5 * sd / std::sqrt(kN));
  EXPECT_NEAR(m.sd, sd, 0.01 * sd);
  EXPECT_GE(m.min, -6.0);
  EXPECT_LE(m.max, 6.0);
  EXPECT_LT(m.min, -5.9);
  EXPECT_GT(m.max, 5.9);
}

TEST(ImpairmentModelTest, NormalJitterHasTheRightMeanAndSd) {
  constexpr int kN = 100000;
  // 10 sd of room below: truncation changes nothing measurable
  const Moments m = JitterMoments(JitterDistribution::kNormal, 50, 5, kN);
  EXPECT_NEAR(m.mean, 0.0, 5 * 5 / std::sqrt(kN));
  EXPECT_NEAR(m.sd, 5.0, 5 * 5 / std::sqrt(2.0 * kN));
}

TEST(ImpairmentModelTest, JitterNeverMakesTheDelayNegative) {
  for (const auto distribution : {JitterDistribution::kNormal, JitterDistribution::kUniform}) {
    for (const double delay_ms : {0.0, 1.0}) {
      const Moments m = JitterMoments(distribution, delay_ms, 5, 20000);
      EXPECT_GE(m.min, -delay_ms);
      EXPECT_GT(m.max, 4.0);
    }
  }
}

TEST(ImpairmentModelTest, FifoWithoutJitterOrReordering) {
  ImpairmentConfig config;
  config.delay_ms = 7;
  config.duplicate = 0.2;
  config.rate_kbps = 20000;
  config.queue_bytes = 1 << 20;
  ImpairmentModel dut(config, 4);
  // sizes vary, so serialisation times differ from datagram to datagram
  const auto delivered =
      Simulate(&dut, 20000, kMs / 4, [](int i) { return static_cast<std::size_t>(40 + (i * 7919) % 1400); });
  for (std::size_t i = 1; i < delivered.size(); ++i) {
    ASSERT_LE(delivered[i - 1].sequence, delivered[i].sequence) << i;
    ASSERT_LE(delivered[i - 1].release_ns, delivered[i].release_ns) << i;
  }
  EXPECT_EQ(dut.stats().reordered, 0u);
  EXPECT_GT(dut.stats().duplicated, 0u);
  ExpectAccountsBalance(dut.stats());
}

TEST(ImpairmentModelTest, ArrivalTimesRunningBackwardsKeepTheOrder) {
  ImpairmentConfig config;
  config.delay_ms = 1;
  ImpairmentModel dut(config, 1);
  const Decision first = dut.Decide(10 * kMs, 100);
  const Decision second = dut.Decide(10 * kMs - 500, 100);  // a stamp 500 ns earlier
  EXPECT_EQ(second.arrival_ns, first.arrival_ns);
  EXPECT_GE(second.release_ns[0], first.release_ns[0]);
}

TEST(ImpairmentModelTest, JitterReorderingIsCounted) {
  ImpairmentConfig config;
  config.delay_ms = 20;
  config.jitter_ms = 5;
  ImpairmentModel dut(config, 5);
  const auto delivered = Simulate(&dut, 20000, kMs);
  EXPECT_GT(dut.stats().reordered, 1000u);  // 1 ms apart, +-5 ms: most are overtaken
  EXPECT_EQ(dut.stats().reordered, CountReordered(delivered));
  EXPECT_EQ(dut.stats().held_back, 0u);
  ExpectAccountsBalance(dut.stats());
}

TEST(ImpairmentModelTest, HeldBackDatagramsAreOvertakenAndCounted) {
  constexpr int kN = 100000;
  constexpr double kReorder = 0.1;
  ImpairmentConfig config;
  config.delay_ms = 2;
  config.reorder = kReorder;
  config.reorder_delay_ms = 10;
  ImpairmentModel dut(config, 6);
  const auto delivered = Simulate(&dut, kN, kMs);
  const ImpairmentStats& stats = dut.stats();
  EXPECT_NEAR(static_cast<double>(stats.held_back), kN * kReorder, BinomialSlack(kN, kReorder));
  // each held-back datagram is overtaken by the next one that is not held back (1 ms later,
  // released 10 ms sooner), except near the end of the stream
  EXPECT_LE(stats.reordered, stats.held_back);
  EXPECT_GE(stats.reordered + 10, stats.held_back);
  EXPECT_EQ(stats.reordered, CountReordered(delivered));
  for (const Delivered& d : delivered) {
    const std::int64_t delay_ns = d.release_ns - d.arrival_ns;
    ASSERT_TRUE(delay_ns == 2 * kMs || delay_ns == 12 * kMs) << delay_ns;
  }
}

TEST(ImpairmentModelTest, DuplicatesAreCountedAndBothCopiesDelivered) {
  constexpr int kN = 100000;
  ImpairmentConfig config;
  config.duplicate = 0.2;
  ImpairmentModel dut(config, 7);
  const auto delivered = Simulate(&dut, kN, kMs);
  const ImpairmentStats& stats = dut.stats();
  EXPECT_NEAR(static_cast<double>(stats.duplicated), kN * 0.2, BinomialSlack(kN, 0.2));
  EXPECT_EQ(stats.forwarded, kN + stats.duplicated);
  EXPECT_EQ(delivered.size(), stats.forwarded);
  EXPECT_EQ(stats.reordered, 0u);  // a copy is not overtaken by its own original
  ExpectAccountsBalance(stats);
}

TEST(ImpairmentModelTest, RateLimitSpacesReleasesBySerialisationTime) {
  ImpairmentConfig config;
  config.delay_ms = 3;
  config.rate_kbps = 1000;  // 125 bytes per ms
  config.queue_bytes = 1 << 30;
  ImpairmentModel dut(config, 1);
  // arrivals every 0.5 ms of up to 1400 bytes: far more than the link carries, so a backlog builds
  const auto size_of = [](int i) { return static_cast<std::size_t>(100 + (i * 7919) % 1300); };
  std::int64_t previous_release_ns = 0;
  for (int i = 0; i < 2000; ++i) {
    const std::int64_t arrival_ns = i * kMs / 2;
    const Decision d = dut.Decide(arrival_ns, size_of(i));
    ASSERT_EQ(d.copies, 1);
    // 8 bits at 1 Mbit/s: 8 us per byte
    const auto serialisation_ns = static_cast<std::int64_t>(size_of(i)) * 8000;
    EXPECT_GE(d.release_ns[0] - arrival_ns - 3 * kMs, serialisation_ns);
    if (i > 0) {
      ASSERT_GE(d.release_ns[0] - previous_release_ns, serialisation_ns) << i;
    }
    previous_release_ns = d.release_ns[0];
  }
  // the link is busy all along: the last release is the sum of every serialisation time
  std::int64_t total_ns = 0;
  for (int i = 0; i < 2000; ++i) total_ns += static_cast<std::int64_t>(size_of(i)) * 8000;
  EXPECT_EQ(previous_release_ns - 3 * kMs, total_ns);
}

TEST(ImpairmentModelTest, QueueOverflowBeyondTheQueueBytes) {
  ImpairmentConfig config;
  config.rate_kbps = 100;  // 1000 bytes take 80 ms
  config.queue_bytes = 10000;
  ImpairmentModel dut(config, 1);
  int passed = 0;
  for (int i = 0; i < 100; ++i) passed += dut.Decide(0, 1000).copies;
  // the k-th datagram finds (k - 1) * 1000 bytes waiting: 10 fit
  EXPECT_EQ(passed, 10);
  EXPECT_EQ(dut.stats().dropped.Get(DropCause::kQueueOverflow), 90u);
  // after 400 ms, 5 of the 10 have left: 5 more fit
  passed = 0;
  for (int i = 0; i < 10; ++i) passed += dut.Decide(400 * kMs, 1000).copies;
  EXPECT_EQ(passed, 5);
  EXPECT_EQ(dut.stats().dropped.Get(DropCause::kQueueOverflow), 95u);
}

TEST(ImpairmentModelTest, NoFreeBufferIsAQueueOverflow) {
  ImpairmentConfig config;
  config.duplicate = 1.0;
  ImpairmentModel dut(config, 1);
  EXPECT_EQ(dut.Decide(0, 100, 0).copies, 0);
  EXPECT_EQ(dut.Decide(0, 100, 1).copies, 1);  // the duplicate finds no buffer
  EXPECT_EQ(dut.Decide(0, 100, 2).copies, 2);
  EXPECT_EQ(dut.stats().dropped.Get(DropCause::kQueueOverflow), 3u);
  EXPECT_EQ(dut.stats().duplicated, 3u);
  EXPECT_EQ(dut.stats().in_flight(), 3u);
}

TEST(ImpairmentModelTest, OversizeDatagramsAreDropped) {
  ImpairmentConfig config;
  config.max_datagram_bytes = 1000;
  ImpairmentModel dut(config, 1);
  EXPECT_EQ(dut.Decide(0, 1000).copies, 1);
  EXPECT_EQ(dut.Decide(0, 1001).copies, 0);
  EXPECT_EQ(dut.Decide(0, 70000).copies, 0);
  EXPECT_EQ(dut.stats().dropped.Get(DropCause::kOversize), 2u);
}

TEST(ImpairmentModelTest, LaterDropsAreCountedByCause) {
  ImpairmentModel dut(ImpairmentConfig{}, 1);
  for (int i = 0; i < 4; ++i) dut.Decide(i, 10);
  EXPECT_EQ(dut.stats().in_flight(), 4u);
  dut.OnUndelivered(DropCause::kSendFailed);
  dut.OnUndelivered(DropCause::kNoDestination);
  dut.OnUndelivered(DropCause::kUnsentAtStop);
  dut.OnDelivered(3, 3, 10);
  EXPECT_EQ(dut.stats().dropped.Get(DropCause::kSendFailed), 1u);
  EXPECT_EQ(dut.stats().dropped.Get(DropCause::kNoDestination), 1u);
  EXPECT_EQ(dut.stats().dropped.Get(DropCause::kUnsentAtStop), 1u);
  EXPECT_EQ(dut.stats().forwarded, 1u);
  EXPECT_EQ(dut.stats().delay.max_ns(), 7);
  ExpectAccountsBalance(dut.stats());
}

TEST(ImpairmentModelTest, PerDatagramPathDoesNotAllocateAfterWarmUp) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  ImpairmentConfig config;
  config.delay_ms = 5;
  config.jitter_ms = 2;
  config.jitter_distribution = JitterDistribution::kNormal;
  config.loss = 0.01;
  config.burst = {.p_good_to_bad = 0.01, .p_bad_to_good = 0.5};
  config.duplicate = 0.01;
  config.reorder = 0.01;
  config.rate_kbps = 10000;
  auto dut = std::make_unique<ImpairmentModel>(config, 1);
  ReleaseQueue queue(4096);
  const auto step = [&](int i) {
    const std::int64_t now_ns = i * kMs / 2;  // the link (0.24 ms per datagram) keeps up
    while (!queue.empty() && queue.Top().release_ns <= now_ns) {
      const ScheduledCopy copy = queue.Pop();
      dut->OnDelivered(copy.sequence, copy.arrival_ns, now_ns);
    }
    const Decision d = dut->Decide(now_ns, 300);
    for (int c = 0; c < d.copies; ++c) {
      queue.Push({d.release_ns[static_cast<std::size_t>(c)], d.arrival_ns, d.sequence, 0, 300});
    }
  };
  for (int i = 0; i < 1000; ++i) step(i);
  testing::AllocationCounter counter;
  for (int i = 1000; i < 100000; ++i) step(i);
  EXPECT_EQ(counter.count(), 0);
  EXPECT_GT(dut->stats().forwarded, 90000u);
}

}  // namespace
}  // namespace haptex::netsim
