#include "libs/contact/contact_state.h"

#include <gtest/gtest.h>

namespace haptex::contact {
namespace {

ContactState C(bool thumb, bool index, bool touch, bool dynamic) {
  return Classify({thumb, index, touch, dynamic});
}

TEST(ContactStateTest, Table1) {
  EXPECT_EQ(C(false, false, false, false), ContactState::kI);
  EXPECT_EQ(C(false, false, false, true), ContactState::kI);
  EXPECT_EQ(C(false, false, true, false), ContactState::kII);
  EXPECT_EQ(C(false, false, true, true), ContactState::kIII);
  EXPECT_EQ(C(true, false, false, false), ContactState::kIV);
  EXPECT_EQ(C(false, true, false, true), ContactState::kV);
  EXPECT_EQ(C(true, true, false, false), ContactState::kVI);
  EXPECT_EQ(C(true, true, false, true), ContactState::kVII);
  EXPECT_EQ(C(true, true, true, false), ContactState::kVIII);
  EXPECT_EQ(C(true, true, true, true), ContactState::kIX);
  // The table's "-": one finger on textile while the fingers touch is named by the textile side.
  EXPECT_EQ(C(true, false, true, false), ContactState::kIV);
}

TEST(ContactStateTest, Names) {
  EXPECT_STREQ(ToString(ContactState::kI), "I");
  EXPECT_STREQ(ToString(ContactState::kIX), "IX");
}

TEST(ContactStateTest, HysteresisDoesNotChatter) {
  Hysteresis h(0.6, 0.4);
  EXPECT_FALSE(h.Update(0.5));
  EXPECT_TRUE(h.Update(0.61));
  EXPECT_TRUE(h.Update(0.5));   // inside the band: stays on
  EXPECT_TRUE(h.Update(0.41));
  EXPECT_FALSE(h.Update(0.39));
  EXPECT_FALSE(h.Update(0.59));  // inside the band: stays off
}

}  // namespace
}  // namespace haptex::contact
