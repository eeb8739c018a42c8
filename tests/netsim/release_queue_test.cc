#include "libs/netsim/release_queue.h"

#include <gtest/gtest.h>

#include "tests/support/allocation_counter.h"

namespace haptex::netsim {
namespace {

ScheduledCopy At(std::int64_t release_ns, std::uint64_t sequence) {
  ScheduledCopy copy;
  copy.release_ns = release_ns;
  copy.sequence = sequence;
  return copy;
}

TEST(ReleaseQueueTest, EarliestFirstAndTiesInPushOrder) {
  ReleaseQueue dut(8);
  ASSERT_TRUE(dut.Push(At(30, 0)));
  ASSERT_TRUE(dut.Push(At(10, 1)));
  ASSERT_TRUE(dut.Push(At(20, 2)));
  ASSERT_TRUE(dut.Push(At(10, 3)));
  ASSERT_TRUE(dut.Push(At(10, 4)));
  EXPECT_EQ(dut.size(), 5u);
  EXPECT_EQ(dut.Top().sequence, 1u);
  for (const std::uint64_t expected : {1u, 3u, 4u, 2u, 0u}) EXPECT_EQ(dut.Pop().sequence, expected);
  EXPECT_TRUE(dut.empty());
}

TEST(ReleaseQueueTest, RefusesBeyondCapacity) {
  ReleaseQueue dut(2);
  EXPECT_TRUE(dut.Push(At(1, 0)));
  EXPECT_TRUE(dut.Push(At(2, 1)));
  EXPECT_FALSE(dut.Push(At(0, 2)));
  EXPECT_EQ(dut.Pop().sequence, 0u);
  EXPECT_TRUE(dut.Push(At(0, 2)));
  EXPECT_EQ(dut.Pop().sequence, 2u);
}

TEST(ReleaseQueueTest, PushAndPopDoNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  ReleaseQueue dut(1024);
  testing::AllocationCounter counter;
  for (int round = 0; round < 10; ++round) {
    for (int i = 0; i < 1024; ++i) dut.Push(At((i * 7919) % 1000, static_cast<std::uint64_t>(i)));
    while (!dut.empty()) dut.Pop();
  }
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::netsim
