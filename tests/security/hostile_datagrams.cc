#include "tests/security/hostile_datagrams.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <span>

#include "haptex/v1/envelope.pb.h"
#include "libs/device/grab_protocol.h"
#include "libs/net/datagram_mac.h"
#include "libs/net/envelope_codec.h"

namespace haptex::security {
namespace {

using Bytes = std::vector<std::uint8_t>;
using net::DropReason;

constexpr std::uint64_t kIntruderEpoch = 2'000'000'000'000'000'000ull;

Bytes RandomBytes(std::size_t n, std::mt19937& rng) {
  Bytes b(n);
  std::uniform_int_distribution<int> byte(0, 255);
  for (auto& x : b) x = static_cast<std::uint8_t>(byte(rng));
  return b;
}

std::size_t Between(std::size_t lo, std::size_t hi, std::mt19937& rng) {
  return std::uniform_int_distribution<std::size_t>(lo, hi)(rng);
}

// An Envelope as the intruder writes it; `sequence` 0 leaves it to the caller.
v1::Envelope Intruder(const net::SessionKey& key, const std::string& intruder, std::uint64_t epoch,
                      std::uint64_t sequence, const std::string& destination) {
  v1::Envelope e;
  e.set_version(net::kEnvelopeVersion);
  e.set_session_id(key.DerivedSessionId());
  e.set_sender(intruder);
  e.set_sender_epoch(epoch);
  e.set_sequence(sequence);
  e.set_send_time_ns(1);
  e.set_destination(destination);
  e.mutable_net_probe();
  return e;
}

Bytes Seal(const net::SessionKey& key, const v1::Envelope& e) {
  net::EnvelopeSealer sealer(key, net::SenderIdentity{"sealer", 1, key.DerivedSessionId()});
  Bytes out(net::kDatagramOverheadBytes + e.ByteSizeLong());
  out.resize(sealer.SealRaw(e, out));
  return out;
}

// Magic, a nonce, `payload` and a valid tag: authentic, whatever the payload is.
Bytes Authentic(const net::SessionKey& key, const Bytes& payload) {
  Bytes out(net::kDatagramHeaderBytes);
  std::copy(net::kDatagramMagic.begin(), net::kDatagramMagic.end(), out.begin());
  net::DatagramMac::NewNonce(out.data() + net::kDatagramMagic.size());
  out.insert(out.end(), payload.begin(), payload.end());
  const std::size_t signed_bytes = out.size();
  out.resize(signed_bytes + net::DatagramMac::kTagBytes);
  net::DatagramMac(key).Compute(std::span<const std::uint8_t>(out.data(), signed_bytes),
                                out.data() + net::kDatagramMagic.size(), out.data() + signed_bytes);
  return out;
}

}  // namespace

std::vector<HostileDatagram> HostileEnvelopes(const net::SessionKey& key, const std::string& destination,
                                              const std::string& intruder, const HostileMix& mix, std::mt19937& rng) {
  std::vector<HostileDatagram> out;
  auto add = [&](Bytes b, DropReason r) { out.push_back({std::move(b), r}); };
  std::uint64_t sequence = 0;
  auto next = [&] { return Intruder(key, intruder, kIntruderEpoch, ++sequence, destination); };

  for (int i = 0; i < mix.garbage; ++i) {
    Bytes b = RandomBytes(Between(net::kDatagramOverheadBytes, 1400, rng), rng);
    b[0] = 0;  // never the magic
    add(std::move(b), DropReason::kBadMagic);
  }
  for (int i = 0; i < mix.truncated; ++i) {
    Bytes b = RandomBytes(Between(1, net::kDatagramOverheadBytes - 1, rng), rng);
    std::copy_n(net::kDatagramMagic.begin(), std::min(b.size(), net::kDatagramMagic.size()), b.begin());
    add(std::move(b), DropReason::kTruncated);
  }
  for (int i = 0; i < mix.oversized; ++i) {
    add(RandomBytes(Between(60001, net::kMaxUdpPayloadBytes, rng), rng), DropReason::kOversized);
  }
  for (int i = 0; i < mix.bit_flips; ++i) {
    Bytes b = Seal(key, next());
    const std::size_t bit = Between(8 * net::kDatagramMagic.size(), 8 * b.size() - 1, rng);
    b[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    add(std::move(b), DropReason::kBadMac);
  }
  const net::SessionKey other_key = net::SessionKey::Generate();
  for (int i = 0; i < mix.wrong_key; ++i) add(Seal(other_key, next()), DropReason::kBadMac);
  for (int i = 0; i < mix.unparsable; ++i) {
    Bytes payload = RandomBytes(Between(1, 200, rng), rng);
    payload[0] = 0xff;  // a tag of wire type 7, which does not exist: no Envelope parses
    add(Authentic(key, payload), DropReason::kUnparsable);
  }
  for (int i = 0; i < mix.wrong_version; ++i) {
    v1::Envelope e = next();
    e.set_version(net::kEnvelopeVersion + 1);
    add(Seal(key, e), DropReason::kWrongVersion);
  }
  for (int i = 0; i < mix.wrong_session; ++i) {
    v1::Envelope e = next();
    e.set_session_id(key.DerivedSessionId() ^ 0x5a5a5a5a5a5a5a5aull);
    add(Seal(key, e), DropReason::kWrongSession);
  }
  for (int i = 0; i < mix.wrong_destination; ++i) {
    v1::Envelope e = next();
    e.set_destination(destination + "_elsewhere");
    add(Seal(key, e), DropReason::kWrongDestination);
  }
  for (int i = 0; i < mix.missing_sender; ++i) {
    v1::Envelope e = next();
    e.clear_sender();
    add(Seal(key, e), DropReason::kMissingSender);
  }
  for (int i = 0; i < mix.unknown_body; ++i) {
    v1::Envelope e = next();
    e.clear_net_probe();
    add(Seal(key, e), DropReason::kUnknownBody);
  }
  // the window starts with the first authentic envelope the receiver accepts from the intruder
  std::vector<Bytes> originals;
  for (int i = 0; i < mix.replays; ++i) {
    originals.push_back(Seal(key, next()));
    add(originals.back(), DropReason::kNone);
  }
  for (const Bytes& b : originals) add(b, DropReason::kReplayed);
  if (mix.stale > 0) {
    std::vector<Bytes> old;
    for (int i = 0; i < mix.stale; ++i) {
      old.push_back(Seal(key, next()));
      add(old.back(), DropReason::kNone);
    }
    for (int i = 0; i < 64; ++i) add(Seal(key, next()), DropReason::kNone);  // a window further
    for (const Bytes& b : old) add(b, DropReason::kStale);
  }
  for (int i = 0; i < mix.stale_epoch; ++i) {
    add(Seal(key, Intruder(key, intruder, kIntruderEpoch - 1, static_cast<std::uint64_t>(i) + 1, destination)),
        DropReason::kStaleEpoch);
  }
  return out;
}

std::vector<std::uint64_t> ExpectedDrops(const std::vector<HostileDatagram>& datagrams) {
  std::vector<std::uint64_t> counts(net::kDropReasonCount, 0);
  for (const HostileDatagram& d : datagrams) ++counts[static_cast<std::size_t>(d.expected)];
  return counts;
}

namespace {

// Every other datagram garbage, the others the encoded frame make(i) returns.
template <class Frame, std::size_t kBytes, class Make, class Encode>
std::vector<Bytes> FramesAndGarbage(int count, std::mt19937& rng, Make make, Encode encode) {
  std::vector<Bytes> out;
  for (int i = 0; i < count; ++i) {
    if (i % 2 == 1) {
      out.push_back(RandomBytes(Between(1, 200, rng), rng));
      continue;
    }
    std::array<std::byte, kBytes> b{};
    encode(make(i), b);
    const auto* p = reinterpret_cast<const std::uint8_t*>(b.data());
    out.emplace_back(p, p + b.size());
  }
  return out;
}

}  // namespace

std::vector<std::vector<std::uint8_t>> ForgedStatusFrames(int count, std::mt19937& rng) {
  return FramesAndGarbage<device::StatusFrame, device::kStatusFrameSize>(
      count, rng,
      [](int i) {
        device::StatusFrame f;
        f.sequence = 0x7fff0000u + static_cast<std::uint32_t>(i);
        f.controller_time_ns = 1'000'000'000ull * static_cast<std::uint64_t>(i + 1);
        for (device::ManipulatorStatus& m : f.manipulators) {
          m.flags = device::manipulator_flags::kCalibrated | device::manipulator_flags::kForceEnabled;
        }
        return f;
      },
      [](const device::StatusFrame& f, std::span<std::byte, device::kStatusFrameSize> b) {
        device::EncodeStatusFrame(f, b);
      });
}

std::vector<std::vector<std::uint8_t>> ForgedCommandFrames(int count, std::mt19937& rng) {
  return FramesAndGarbage<device::CommandFrame, device::kCommandFrameSize>(
      count, rng,
      [](int i) {
        device::CommandFrame c;
        c.sequence = 0x7fff0000u + static_cast<std::uint32_t>(i);
        for (device::ManipulatorCommand& m : c.manipulators) {
          m.force_D_N = {0.0f, 20.0f, 0.0f};
          m.flags = device::command_flags::kForceEnable;
        }
        return c;
      },
      [](const device::CommandFrame& c, std::span<std::byte, device::kCommandFrameSize> b) {
        device::EncodeCommandFrame(c, b);
      });
}

}  // namespace haptex::security
