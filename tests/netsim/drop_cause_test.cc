#include "libs/netsim/drop_cause.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace haptex::netsim {
namespace {

TEST(DropCauseTest, EveryCauseHasItsOwnName) {
  std::set<std::string> names;
  for (std::size_t i = 0; i < kDropCauseCount; ++i) {
    names.insert(std::string(DropCauseName(static_cast<DropCause>(i))));
  }
  EXPECT_EQ(names.size(), kDropCauseCount);
  EXPECT_EQ(names.count("unknown"), 0u);
  EXPECT_EQ(DropCauseName(DropCause::kBurstLoss), "burst_loss");
  EXPECT_EQ(DropCauseName(DropCause::kQueueOverflow), "queue_overflow");
}

TEST(DropCauseTest, CountsAddUpPerCauseAndInTotal) {
  DropCounts counts;
  EXPECT_EQ(counts.Total(), 0u);
  counts.Add(DropCause::kLoss);
  counts.Add(DropCause::kLoss);
  counts.Add(DropCause::kUnsentAtStop);
  EXPECT_EQ(counts.Get(DropCause::kLoss), 2u);
  EXPECT_EQ(counts.Get(DropCause::kUnsentAtStop), 1u);
  EXPECT_EQ(counts.Get(DropCause::kOversize), 0u);
  EXPECT_EQ(counts.Total(), 3u);
}

}  // namespace
}  // namespace haptex::netsim
