#include "libs/net/replay_window.h"

#include <gtest/gtest.h>

#include <string>

namespace haptex::net {
namespace {

TEST(ReplayWindowTest, AcceptsEachSequenceOnceInAnyOrderWithinWindow) {
  ReplayWindow window;
  EXPECT_EQ(window.Check(1), DropReason::kNone);
  EXPECT_EQ(window.Check(3), DropReason::kNone);
  EXPECT_EQ(window.Check(2), DropReason::kNone);  // reordered, still fresh
  EXPECT_EQ(window.Check(2), DropReason::kReplayed);
  EXPECT_EQ(window.Check(3), DropReason::kReplayed);
  EXPECT_EQ(window.Check(0), DropReason::kStale);  // sequences start at 1
}

TEST(ReplayWindowTest, OlderThanWindowIsStale) {
  ReplayWindow window;
  EXPECT_EQ(window.Check(5), DropReason::kNone);
  EXPECT_EQ(window.Check(5 + ReplayWindow::kWindow), DropReason::kNone);
  EXPECT_EQ(window.Check(5), DropReason::kStale);
  EXPECT_EQ(window.Check(6), DropReason::kNone);     // just inside
  EXPECT_EQ(window.Check(1000), DropReason::kNone);  // big jump clears the bitmap
  EXPECT_EQ(window.Check(999), DropReason::kNone);
  EXPECT_EQ(window.Check(1000), DropReason::kReplayed);
}

TEST(SenderTableTest, SendersAreIndependent) {
  SenderTable table;
  EXPECT_EQ(table.Check("a", 10, 1), DropReason::kNone);
  EXPECT_EQ(table.Check("b", 10, 1), DropReason::kNone);
  EXPECT_EQ(table.Check("a", 10, 1), DropReason::kReplayed);
  EXPECT_EQ(table.size(), 2u);
}

TEST(SenderTableTest, RestartWithLaterEpochResetsAndEarlierEpochIsStale) {
  SenderTable table;
  EXPECT_EQ(table.Check("bridge", 100, 50), DropReason::kNone);
  EXPECT_EQ(table.Check("bridge", 200, 1), DropReason::kNone);  // restarted
  EXPECT_EQ(table.restarts(), 1u);
  EXPECT_EQ(table.Check("bridge", 100, 51), DropReason::kStaleEpoch);  // replay of the old run
  EXPECT_EQ(table.Check("bridge", 200, 1), DropReason::kReplayed);
  EXPECT_EQ(table.Check("bridge", 300, 0), DropReason::kStale);  // bad first datagram: no reset
  EXPECT_EQ(table.restarts(), 1u);
  EXPECT_EQ(table.Check("bridge", 200, 2), DropReason::kNone);
}

TEST(SenderTableTest, BadFirstDatagramTakesNoSlot) {
  SenderTable table;
  EXPECT_EQ(table.Check("newcomer", 5, 0), DropReason::kStale);
  EXPECT_EQ(table.size(), 0u);
  EXPECT_EQ(table.Check("newcomer", 5, 1), DropReason::kNone);
  EXPECT_EQ(table.size(), 1u);
}

TEST(SenderTableTest, MissingIdentityAndFullTable) {
  SenderTable table;
  EXPECT_EQ(table.Check("", 1, 1), DropReason::kMissingSender);
  EXPECT_EQ(table.Check("x", 0, 1), DropReason::kMissingSender);
  EXPECT_EQ(table.Check(std::string(SenderTable::kMaxNameBytes + 1, 'n'), 1, 1), DropReason::kMissingSender);
  for (std::size_t i = 0; i < SenderTable::kMaxSenders; ++i) {
    EXPECT_EQ(table.Check("s" + std::to_string(i), 1, 1), DropReason::kNone);
  }
  EXPECT_EQ(table.Check("one_too_many", 1, 1), DropReason::kTooManySenders);
  EXPECT_EQ(table.Check("s0", 1, 2), DropReason::kNone);  // known senders still work
}

}  // namespace
}  // namespace haptex::net
