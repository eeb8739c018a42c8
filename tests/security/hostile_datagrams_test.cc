// The campaign's attacker is right about what it sends: a receiver that answers to the
// destination counts every hostile datagram under the reason it was made for, and the forged
// GRAB frames are well formed (only the sender's address gives them away).

#include "tests/security/hostile_datagrams.h"

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <span>

#include "haptex/v1/envelope.pb.h"
#include "libs/device/grab_protocol.h"
#include "libs/net/envelope_codec.h"

namespace haptex::security {
namespace {

TEST(HostileDatagramsTest, EachIsCountedUnderTheReasonItWasMadeFor) {
  const net::SessionKey key = net::SessionKey::Generate();
  std::mt19937 rng(7);
  const std::vector<HostileDatagram> datagrams = HostileEnvelopes(key, "global_sim", "intruder", HostileMix{}, rng);
  net::EnvelopeOpener opener(key, key.DerivedSessionId());
  opener.AcceptDestinations({"global_sim"});
  for (std::size_t i = 0; i < datagrams.size(); ++i) {
    v1::Envelope envelope;
    const net::DropReason reason = opener.Open(datagrams[i].bytes, &envelope);
    EXPECT_EQ(net::DropReasonName(reason), net::DropReasonName(datagrams[i].expected)) << "datagram " << i;
  }
  const std::vector<std::uint64_t> expected = ExpectedDrops(datagrams);
  for (std::size_t r = 1; r < net::kDropReasonCount; ++r) {
    const auto reason = static_cast<net::DropReason>(r);
    EXPECT_EQ(opener.counters().Get(reason), expected[r]) << net::DropReasonName(reason);
  }
  // every reason a datagram from outside can be dropped for is exercised
  for (const net::DropReason r :
       {net::DropReason::kBadMagic, net::DropReason::kTruncated, net::DropReason::kOversized, net::DropReason::kBadMac,
        net::DropReason::kUnparsable, net::DropReason::kWrongVersion, net::DropReason::kWrongSession,
        net::DropReason::kWrongDestination, net::DropReason::kMissingSender, net::DropReason::kUnknownBody,
        net::DropReason::kReplayed, net::DropReason::kStale, net::DropReason::kStaleEpoch}) {
    EXPECT_GT(expected[static_cast<std::size_t>(r)], 0u) << net::DropReasonName(r);
  }
}

TEST(HostileDatagramsTest, ForgedFramesAreWellFormedOrGarbage) {
  std::mt19937 rng(3);
  int valid = 0;
  for (const auto& b : ForgedStatusFrames(10, rng)) {
    device::StatusFrame f;
    const auto bytes = std::as_bytes(std::span(b));
    if (device::DecodeStatusFrame(bytes, device::GrabValueLimits{}, &f) == device::FrameError::kNone) ++valid;
  }
  EXPECT_EQ(valid, 5);
  valid = 0;
  for (const auto& b : ForgedCommandFrames(10, rng)) {
    device::CommandFrame c;
    const auto bytes = std::as_bytes(std::span(b));
    if (device::DecodeCommandFrame(bytes, device::GrabValueLimits{}, &c) == device::FrameError::kNone) {
      ++valid;
      EXPECT_FLOAT_EQ(c.manipulators[0].force_D_N.norm(), 20.0f);
    }
  }
  EXPECT_EQ(valid, 5);
}

}  // namespace
}  // namespace haptex::security
