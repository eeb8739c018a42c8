#include "libs/net/envelope_codec.h"

#include <gtest/gtest.h>

#include <google/protobuf/arena.h>

#include <random>
#include <vector>

#include "tests/support/allocation_counter.h"

namespace haptex::net {
namespace {

constexpr std::uint64_t kSession = 0x5e55;

class EnvelopeCodecTest : public ::testing::Test {
 protected:
  EnvelopeCodecTest()
      : key_(SessionKey::Generate()),
        sealer_(key_, {"local_contact", 1000, kSession}),
        opener_(key_, kSession, 60000),
        buffer_(kMaxUdpPayloadBytes) {
    auto* finger = force_model_.add_fingers();
    finger->set_finger(v1::FINGER_THUMB);
    finger->mutable_f0_w_n()->set_z(1.5);
    for (int i = 0; i < 9; ++i) finger->add_stiffness_w_n_per_m(i == 0 || i == 4 || i == 8 ? -1250.0 : 0.0);
    finger->set_ttl_s(0.01);
    force_model_.set_based_on_controller_sequence(77);
  }

  std::vector<std::uint8_t> SealForceModel(EnvelopeSealer& sealer) {
    const std::size_t n = sealer.Seal(force_model_, 123456789, "receiver", buffer_);
    EXPECT_GT(n, 0u);
    return {buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(n)};
  }
  std::vector<std::uint8_t> SealForceModel() { return SealForceModel(sealer_); }

  DropReason Open(const std::vector<std::uint8_t>& datagram) { return opener_.Open(datagram, &envelope_); }

  // A valid header for SealRaw-based cases.
  v1::Envelope Header() const {
    v1::Envelope e;
    e.set_version(kEnvelopeVersion);
    e.set_session_id(kSession);
    e.set_sender("forger");
    e.set_sender_epoch(5);
    e.set_sequence(1);
    return e;
  }
  std::vector<std::uint8_t> SealRaw(const v1::Envelope& e) {
    const std::size_t n = sealer_.SealRaw(e, buffer_);
    EXPECT_GT(n, 0u);
    return {buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(n)};
  }

  SessionKey key_;
  EnvelopeSealer sealer_;
  EnvelopeOpener opener_;
  std::vector<std::uint8_t> buffer_;
  v1::ForceModel force_model_;
  v1::Envelope envelope_;
};

// The destination is under the MAC: an envelope captured on its way to one service and replayed to
// another is dropped there, before its sequence is looked at; each receiver answers to its own name
// and its aliases.
TEST_F(EnvelopeCodecTest, AnEnvelopeForAnotherServiceIsDroppedAsWrongDestination) {
  EnvelopeOpener bridge(key_, kSession, 60000), tactile(key_, kSession, 60000);
  bridge.AcceptDestinations({"device_bridge", "bridge"});
  tactile.AcceptDestinations({"tactile"});
  const auto seal_to = [&](std::string_view destination) {
    const std::size_t n = sealer_.Seal(force_model_, 1, destination, buffer_);
    EXPECT_GT(n, 0u);
    return std::vector<std::uint8_t>(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(n));
  };
  const auto to_bridge = seal_to("bridge");
  EXPECT_EQ(bridge.Open(to_bridge, &envelope_), DropReason::kNone);
  EXPECT_EQ(envelope_.destination(), "bridge");
  EXPECT_EQ(tactile.Open(to_bridge, &envelope_), DropReason::kWrongDestination) << "replayed to another service";
  EXPECT_EQ(bridge.Open(seal_to("device_bridge"), &envelope_), DropReason::kNone) << "its own name";
  EXPECT_EQ(bridge.Open(seal_to("tactile"), &envelope_), DropReason::kWrongDestination);
  EXPECT_EQ(bridge.Open(seal_to(""), &envelope_), DropReason::kWrongDestination) << "unaddressed";
  EXPECT_EQ(tactile.counters().Get(DropReason::kWrongDestination), 1u);
  EXPECT_EQ(bridge.counters().Get(DropReason::kWrongDestination), 2u);
  EXPECT_EQ(sealer_.Seal(force_model_, 1, std::string(48, 'x'), buffer_), 0u) << "a name longer than any sender's";
}

TEST_F(EnvelopeCodecTest, RoundTripKeepsHeaderAndBody) {
  const auto datagram = SealForceModel();
  ASSERT_EQ(Open(datagram), DropReason::kNone);
  EXPECT_EQ(envelope_.version(), kEnvelopeVersion);
  EXPECT_EQ(envelope_.session_id(), kSession);
  EXPECT_EQ(envelope_.sender(), "local_contact");
  EXPECT_EQ(envelope_.sender_epoch(), 1000u);
  EXPECT_EQ(envelope_.sequence(), 1u);
  EXPECT_EQ(envelope_.send_time_ns(), 123456789);
  ASSERT_EQ(envelope_.body_case(), v1::Envelope::kForceModel);
  EXPECT_EQ(envelope_.force_model().SerializeAsString(), force_model_.SerializeAsString());
  EXPECT_EQ(opener_.counters().accepted(), 1u);
  // The hand-written header is exactly protobuf's own encoding of the same Envelope.
  v1::Envelope expected = envelope_;
  EXPECT_EQ(std::vector<std::uint8_t>(datagram.begin() + kDatagramHeaderBytes, datagram.end() - 16), [&] {
    auto s = expected.SerializeAsString();
    return std::vector<std::uint8_t>(s.begin(), s.end());
  }());
}

TEST_F(EnvelopeCodecTest, SequenceIncreasesPerDatagram) {
  SealForceModel();
  SealForceModel();
  const auto third = SealForceModel();
  ASSERT_EQ(Open(third), DropReason::kNone);
  EXPECT_EQ(envelope_.sequence(), 3u);
  EXPECT_EQ(sealer_.next_sequence(), 4u);
}

TEST_F(EnvelopeCodecTest, TooSmallBufferSealsNothing) {
  std::vector<std::uint8_t> small(20);
  EXPECT_EQ(sealer_.Seal(force_model_, 0, "receiver", small), 0u);
  EXPECT_EQ(sealer_.next_sequence(), 1u);
}

TEST_F(EnvelopeCodecTest, TruncatedDatagramsAreDropped) {
  auto datagram = SealForceModel();
  EXPECT_EQ(Open({datagram.begin(), datagram.begin() + 40}), DropReason::kTruncated);
  EXPECT_EQ(Open({}), DropReason::kTruncated);
  // Cut by one byte: the tag no longer matches.
  EXPECT_EQ(Open({datagram.begin(), datagram.end() - 1}), DropReason::kBadMac);
  EXPECT_EQ(opener_.counters().Get(DropReason::kTruncated), 2u);
}

TEST_F(EnvelopeCodecTest, OversizedDatagramIsDropped) {
  EnvelopeOpener small_opener(key_, kSession, 64);
  const auto datagram = SealForceModel();
  ASSERT_GT(datagram.size(), 64u);
  EXPECT_EQ(small_opener.Open(datagram, &envelope_), DropReason::kOversized);
  EXPECT_EQ(small_opener.counters().Get(DropReason::kOversized), 1u);
}

TEST_F(EnvelopeCodecTest, BadMagicIsDropped) {
  auto datagram = SealForceModel();
  datagram[3] = 0x01;  // another framing version
  EXPECT_EQ(Open(datagram), DropReason::kBadMagic);
}

TEST_F(EnvelopeCodecTest, AlteredBytesAndWrongKeyFailTheMac) {
  auto datagram = SealForceModel();
  datagram[datagram.size() / 2] ^= 0x10;
  EXPECT_EQ(Open(datagram), DropReason::kBadMac);
  EnvelopeSealer stranger(SessionKey::Generate(), {"local_contact", 1000, kSession});
  EXPECT_EQ(Open(SealForceModel(stranger)), DropReason::kBadMac);
  EXPECT_EQ(opener_.counters().Get(DropReason::kBadMac), 2u);
}

TEST_F(EnvelopeCodecTest, AuthenticGarbageIsUnparsable) {
  // Correct magic, nonce and tag around bytes that are not an Envelope (a truncated varint).
  std::vector<std::uint8_t> datagram(kDatagramMagic.begin(), kDatagramMagic.end());
  datagram.resize(kDatagramHeaderBytes);
  DatagramMac::NewNonce(datagram.data() + kDatagramMagic.size());
  for (int i = 0; i < 12; ++i) datagram.push_back(0xff);
  datagram.resize(datagram.size() + DatagramMac::kTagBytes);
  DatagramMac(key_).Compute({datagram.data(), datagram.size() - DatagramMac::kTagBytes},
                            datagram.data() + kDatagramMagic.size(),
                            datagram.data() + datagram.size() - DatagramMac::kTagBytes);
  EXPECT_EQ(Open(datagram), DropReason::kUnparsable);
}

TEST_F(EnvelopeCodecTest, WrongVersionIsDropped) {
  v1::Envelope e = Header();
  e.set_version(2);
  e.mutable_control()->set_command(v1::Control::COMMAND_ZERO_FORCE);
  EXPECT_EQ(Open(SealRaw(e)), DropReason::kWrongVersion);
}

TEST_F(EnvelopeCodecTest, WrongSessionIsDropped) {
  EnvelopeSealer other_run(key_, {"local_contact", 1000, kSession + 1});
  EXPECT_EQ(Open(SealForceModel(other_run)), DropReason::kWrongSession);
}

TEST_F(EnvelopeCodecTest, MissingBodyAndUnknownBodyAreDropped) {
  EXPECT_EQ(Open(SealRaw(Header())), DropReason::kUnknownBody);
  // A body of a newer schema: field 99 is not in our oneof and lands in unknown fields.
  const std::size_t n = sealer_.SealBody(force_model_, 99, 0, "receiver", buffer_);
  ASSERT_GT(n, 0u);
  EXPECT_EQ(Open({buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(n)}), DropReason::kUnknownBody);
  EXPECT_EQ(opener_.counters().Get(DropReason::kUnknownBody), 2u);
}

TEST_F(EnvelopeCodecTest, MissingSenderIsDropped) {
  v1::Envelope e = Header();
  e.clear_sender();
  e.mutable_control();
  EXPECT_EQ(Open(SealRaw(e)), DropReason::kMissingSender);
}

TEST_F(EnvelopeCodecTest, ReplayedAndStaleSequencesAreDropped) {
  const auto first = SealForceModel();
  ASSERT_EQ(Open(first), DropReason::kNone);
  EXPECT_EQ(Open(first), DropReason::kReplayed);
  std::vector<std::uint8_t> later;
  for (std::uint64_t i = 0; i < ReplayWindow::kWindow + 5; ++i) later = SealForceModel();
  const auto reordered = SealForceModel();
  const auto newest = SealForceModel();
  ASSERT_EQ(Open(newest), DropReason::kNone);
  EXPECT_EQ(Open(reordered), DropReason::kNone);  // late but inside the window
  EXPECT_EQ(Open(first), DropReason::kStale);
  EXPECT_EQ(opener_.counters().Get(DropReason::kReplayed), 1u);
  EXPECT_EQ(opener_.counters().Get(DropReason::kStale), 1u);
}

TEST_F(EnvelopeCodecTest, EarlierEpochOfARestartedSenderIsDropped) {
  EnvelopeSealer old_run(key_, {"device_bridge", 100, kSession});
  EnvelopeSealer new_run(key_, {"device_bridge", 200, kSession});
  const auto old_datagram = SealForceModel(old_run);
  ASSERT_EQ(Open(SealForceModel(new_run)), DropReason::kNone);
  EXPECT_EQ(Open(old_datagram), DropReason::kStaleEpoch);
}

TEST_F(EnvelopeCodecTest, FloodOfGarbageIsCountedAndNeverAccepted) {
  std::mt19937 rng(1234);
  std::uniform_int_distribution<int> size(0, 2000);
  std::uniform_int_distribution<int> byte(0, 255);
  constexpr int kDatagrams = 20000;
  std::vector<std::uint8_t> datagram;
  for (int i = 0; i < kDatagrams; ++i) {
    datagram.resize(static_cast<std::size_t>(size(rng)));
    for (auto& b : datagram) b = static_cast<std::uint8_t>(byte(rng));
    if (i % 2 == 0 && datagram.size() >= 4) {
      std::copy(kDatagramMagic.begin(), kDatagramMagic.end(), datagram.begin());  // get past magic
    }
    EXPECT_NE(Open(datagram), DropReason::kNone);
  }
  EXPECT_EQ(opener_.counters().TotalDropped(), static_cast<std::uint64_t>(kDatagrams));
  EXPECT_EQ(opener_.counters().accepted(), 0u);
  // A real datagram still gets through afterwards.
  EXPECT_EQ(Open(SealForceModel()), DropReason::kNone);
}

TEST_F(EnvelopeCodecTest, BadIdentityIsRefusedAtConstruction) {
  EXPECT_THROW(EnvelopeSealer(key_, {"", 1, 1}), std::invalid_argument);
  EXPECT_THROW(EnvelopeSealer(key_, {"x", 0, 1}), std::invalid_argument);
  EXPECT_THROW(EnvelopeSealer(key_, {"x", 1, 0}), std::invalid_argument);
  EXPECT_THROW(EnvelopeOpener(key_, 0), std::invalid_argument);
  EXPECT_THROW(EnvelopeOpener(key_, 1, 70000), std::invalid_argument);
}

TEST_F(EnvelopeCodecTest, WarmedUpSealAndOpenDoNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting is off";
  // Received Envelopes live on an arena over a fixed block, reset per datagram (as in Messenger):
  // parsing into a reused heap Envelope would free and reallocate its oneof body every time.
  std::vector<char> block(1 << 16);
  google::protobuf::ArenaOptions options;
  options.initial_block = block.data();
  options.initial_block_size = block.size();
  google::protobuf::Arena arena(options);
  auto open_on_arena = [&](std::size_t n) {
    arena.Reset();
    auto* e = google::protobuf::Arena::CreateMessage<v1::Envelope>(&arena);
    return opener_.Open({buffer_.data(), n}, e);
  };
  for (int i = 0; i < 10; ++i)
    ASSERT_EQ(open_on_arena(sealer_.Seal(force_model_, i, "receiver", buffer_)), DropReason::kNone);
  testing::AllocationCounter counter;
  for (int i = 0; i < 100; ++i) {
    const std::size_t n = sealer_.Seal(force_model_, i, "receiver", buffer_);
    ASSERT_EQ(open_on_arena(n), DropReason::kNone);
  }
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::net
