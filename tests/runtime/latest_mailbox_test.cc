#include "libs/runtime/latest_mailbox.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace haptex::runtime {
namespace {

struct Pose {
  std::uint64_t sequence = 0;
  double x = 0, y = 0, z = 0;  // always sequence, 2*sequence, 3*sequence: a torn read would show
};

TEST(LatestMailboxTest, ReadReturnsNewestOnceThenNothing) {
  LatestMailbox<int> box;
  int value = -1;
  EXPECT_FALSE(box.Read(&value));
  box.Write(1);
  box.Write(2);
  box.Write(3);
  ASSERT_TRUE(box.Read(&value));
  EXPECT_EQ(value, 3);
  EXPECT_FALSE(box.Read(&value));
  box.Write(4);
  ASSERT_TRUE(box.Read(&value));
  EXPECT_EQ(value, 4);
}

TEST(LatestMailboxTest, ConcurrentReaderNeverSeesTornOrOlderValues) {
  LatestMailbox<Pose> box;
  constexpr std::uint64_t kWrites = 200000;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (std::uint64_t i = 1; i <= kWrites; ++i) {
      const auto d = static_cast<double>(i);
      box.Write(Pose{i, d, 2 * d, 3 * d});
    }
    done.store(true);
  });
  std::uint64_t last = 0;
  std::uint64_t reads = 0;
  Pose pose;
  for (;;) {
    const bool finished = done.load();
    if (!box.Read(&pose)) {
      if (finished) break;  // the writer's last value was already read
      std::this_thread::yield();
      continue;
    }
    ++reads;
    const auto d = static_cast<double>(pose.sequence);
    ASSERT_EQ(pose.x, d);
    ASSERT_EQ(pose.y, 2 * d);
    ASSERT_EQ(pose.z, 3 * d);
    ASSERT_GT(pose.sequence, last);
    last = pose.sequence;
  }
  writer.join();
  EXPECT_EQ(last, kWrites);  // the final value is never lost
  EXPECT_GT(reads, 0u);
}

}  // namespace
}  // namespace haptex::runtime
