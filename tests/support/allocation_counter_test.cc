#include "tests/support/allocation_counter.h"

#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace haptex::testing {
namespace {

TEST(AllocationCounterTest, CountsNewAndMalloc) {
  if (!AllocationCountingSupported()) GTEST_SKIP() << "allocation counting is off under ASan";
  AllocationCounter counter;
  auto p = std::make_unique<int>(3);
  void* volatile raw = std::malloc(16);  // volatile: the compiler may not elide the pair
  std::free(raw);
  std::vector<double> v(100);
  EXPECT_EQ(counter.count(), 3);
}

TEST(AllocationCounterTest, ZeroWhenNothingAllocates) {
  if (!AllocationCountingSupported()) GTEST_SKIP() << "allocation counting is off under ASan";
  std::vector<double> v;
  v.reserve(64);
  AllocationCounter counter;
  for (int i = 0; i < 64; ++i) v.push_back(i);
  EXPECT_EQ(counter.count(), 0);
}

TEST(AllocationCounterTest, IgnoresOtherThreads) {
  if (!AllocationCountingSupported()) GTEST_SKIP() << "allocation counting is off under ASan";
  std::thread worker;  // created outside the counted scope
  AllocationCounter counter;
  const auto before = counter.count();
  std::thread([] { auto p = std::make_unique<std::vector<int>>(1000); }).join();
  // Creating the thread allocates its state on this thread; the worker's own allocation is not ours.
  EXPECT_LE(counter.count() - before, 2);
}

}  // namespace
}  // namespace haptex::testing
