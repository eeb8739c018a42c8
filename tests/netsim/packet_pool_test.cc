#include "libs/netsim/packet_pool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>

#include "tests/support/allocation_counter.h"

namespace haptex::netsim {
namespace {

PacketPoolSizes Small() { return {.small_bytes = 100, .small_count = 3, .large_bytes = 1000, .large_count = 2}; }

TEST(PacketPoolTest, SmallDatagramsTakeSmallBuffersThenLargeOnes) {
  PacketPool dut(Small());
  EXPECT_EQ(dut.capacity(), 5u);
  EXPECT_EQ(dut.FreeFor(100), 5u);
  EXPECT_EQ(dut.FreeFor(101), 2u);
  EXPECT_EQ(dut.FreeFor(1001), 0u);
  std::set<std::uint32_t> ids;
  for (int i = 0; i < 5; ++i) {
    const auto id = dut.Acquire(50);
    ASSERT_TRUE(id.has_value());
    ids.insert(*id);
    EXPECT_GE(dut.Buffer(*id).size(), 50u);
  }
  EXPECT_EQ(ids.size(), 5u);
  EXPECT_FALSE(dut.Acquire(1).has_value());
  EXPECT_EQ(dut.in_use(), 5u);
  for (const auto id : ids) dut.Release(id);
  EXPECT_EQ(dut.in_use(), 0u);
}

TEST(PacketPoolTest, LargeDatagramsOnlyTakeLargeBuffers) {
  PacketPool dut(Small());
  const auto a = dut.Acquire(1000);
  const auto b = dut.Acquire(500);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(dut.Buffer(*a).size(), 1000u);
  EXPECT_FALSE(dut.Acquire(101).has_value());
  EXPECT_TRUE(dut.Acquire(100).has_value());
  EXPECT_FALSE(dut.Acquire(5000).has_value());
}

TEST(PacketPoolTest, BuffersDoNotOverlap) {
  PacketPool dut(Small());
  std::vector<std::uint32_t> ids;
  while (const auto id = dut.Acquire(1)) ids.push_back(*id);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    auto buffer = dut.Buffer(ids[i]);
    std::fill(buffer.begin(), buffer.end(), static_cast<std::uint8_t>(i + 1));
  }
  for (std::size_t i = 0; i < ids.size(); ++i) {
    for (const std::uint8_t byte : dut.Buffer(ids[i])) ASSERT_EQ(byte, i + 1);
  }
}

TEST(PacketPoolTest, RefusesNonsenseSizes) {
  EXPECT_THROW(PacketPool({.small_bytes = 0}), std::invalid_argument);
  EXPECT_THROW(PacketPool({.small_bytes = 100, .small_count = 1, .large_bytes = 50, .large_count = 1}),
               std::invalid_argument);
  EXPECT_THROW(PacketPool({.small_bytes = 1, .small_count = 0, .large_bytes = 1, .large_count = 0}),
               std::invalid_argument);
}

TEST(PacketPoolTest, AcquireAndReleaseDoNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  PacketPool dut(PacketPoolSizes{});
  testing::AllocationCounter counter;
  for (int i = 0; i < 100000; ++i) {
    const auto id = dut.Acquire(static_cast<std::size_t>(i % 3000));
    dut.Release(*id);
  }
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::netsim
