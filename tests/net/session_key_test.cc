#include "libs/net/session_key.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace haptex::net {
namespace {

constexpr char kHex[] = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";

TEST(SessionKeyTest, HexRoundTrip) {
  const SessionKey key = SessionKey::FromHex(kHex);
  EXPECT_EQ(key.ToHex(), kHex);
  EXPECT_EQ(key.bytes()[31], 0x1f);
  EXPECT_EQ(SessionKey::FromHex(std::string("  ") + kHex + "\n").ToHex(), kHex);
}

TEST(SessionKeyTest, RejectsBadHexWithClearMessage) {
  try {
    SessionKey::FromHex("abc");
    FAIL() << "short key accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("64 hex digits"), std::string::npos) << e.what();
  }
  std::string bad = kHex;
  bad[10] = 'z';
  EXPECT_THROW(SessionKey::FromHex(bad), std::invalid_argument);
}

TEST(SessionKeyTest, GeneratedKeysDiffer) { EXPECT_NE(SessionKey::Generate().ToHex(), SessionKey::Generate().ToHex()); }

TEST(SessionKeyTest, DerivedSessionIdIsStableAndKeyDependent) {
  const SessionKey a = SessionKey::FromHex(kHex);
  EXPECT_EQ(a.DerivedSessionId(), SessionKey::FromHex(kHex).DerivedSessionId());
  EXPECT_NE(a.DerivedSessionId(), SessionKey::Generate().DerivedSessionId());
  EXPECT_NE(a.DerivedSessionId(), 0u);
}

}  // namespace
}  // namespace haptex::net
