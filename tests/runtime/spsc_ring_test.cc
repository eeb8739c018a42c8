#include "libs/runtime/spsc_ring.h"

#include <gtest/gtest.h>

#include <memory>
#include <thread>

namespace haptex::runtime {
namespace {

TEST(SpscRingTest, FullRingRefusesAndEmptyRingHasNothing) {
  SpscRing<int, 4> ring;
  int item = 0;
  EXPECT_FALSE(ring.TryPop(&item));
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.TryPush(i));
  EXPECT_FALSE(ring.TryPush(99));
  EXPECT_EQ(ring.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(ring.TryPop(&item));
    EXPECT_EQ(item, i);
  }
}

TEST(SpscRingTest, ConcurrentTransferKeepsEveryItemInOrder) {
  SpscRing<std::uint64_t, 256> ring;
  constexpr std::uint64_t kItems = 100000;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kItems;) {
      if (ring.TryPush(i)) {
        ++i;
      } else {
        std::this_thread::yield();  // two cores shared with other tests: do not spin
      }
    }
  });
  std::uint64_t expected = 0;
  std::uint64_t item = 0;
  while (expected < kItems) {
    if (ring.TryPop(&item)) {
      ASSERT_EQ(item, expected);
      ++expected;
    } else {
      std::this_thread::yield();
    }
  }
  producer.join();
  EXPECT_EQ(ring.size(), 0u);
}

}  // namespace
}  // namespace haptex::runtime

namespace haptex::runtime {
namespace {

// Ownership crosses threads through the ring: a refused push leaves the item with the caller, and
// a popped slot no longer owns what it handed out.
TEST(SpscRingTest, MoveOnlyItemsChangeOwnerOrStayWithTheCaller) {
  SpscRing<std::unique_ptr<int>, 2> ring;
  auto a = std::make_unique<int>(1), b = std::make_unique<int>(2), c = std::make_unique<int>(3);
  EXPECT_TRUE(ring.TryPush(std::move(a)));
  EXPECT_TRUE(ring.TryPush(std::move(b)));
  EXPECT_EQ(a, nullptr);
  EXPECT_FALSE(ring.TryPush(std::move(c)));
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(*c, 3);
  std::unique_ptr<int> out;
  ASSERT_TRUE(ring.TryPop(&out));
  EXPECT_EQ(*out, 1);
  ASSERT_TRUE(ring.TryPop(&out));
  EXPECT_EQ(*out, 2);
  EXPECT_FALSE(ring.TryPop(&out));
  EXPECT_EQ(*out, 2) << "a failed pop leaves the target alone";
}

}  // namespace
}  // namespace haptex::runtime
