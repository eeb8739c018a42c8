#include "libs/device/grab_protocol.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "libs/device/crc32c.h"
#include "libs/device/deterministic_rng.h"
#include "tests/support/allocation_counter.h"

namespace haptex::device {
namespace {

using StatusBytes = std::array<std::byte, kStatusFrameSize>;
using CommandBytes = std::array<std::byte, kCommandFrameSize>;

StatusFrame SampleStatus() {
  StatusFrame f;
  f.controller_flags = controller_flags::kCommandRejected;
  f.sequence = 0xA1B2C3D4u;
  f.echo_host_sequence = 77;
  f.controller_time_ns = 0x0102030405060708ull;
  f.manipulators[0].p_D_m = {0.012f, -0.034f, 0.056f};
  f.manipulators[0].q_DF = Eigen::Quaternionf(Eigen::AngleAxisf(0.3f, Eigen::Vector3f(1, 2, 3).normalized()));
  f.manipulators[0].force_D_N = {1.5f, -2.25f, 3.0f};
  f.manipulators[0].flags = manipulator_flags::kCalibrated | manipulator_flags::kForceEnabled;
  f.manipulators[1].p_D_m = {-0.19f, 0.09f, -0.14f};
  f.manipulators[1].q_DF = Eigen::Quaternionf(0.5f, 0.5f, -0.5f, 0.5f);
  f.manipulators[1].force_D_N = {0.0f, 0.0f, -19.5f};
  f.manipulators[1].flags = manipulator_flags::kCalibrated | manipulator_flags::kWorkspaceLimit;
  return f;
}

CommandFrame SampleCommand() {
  CommandFrame c;
  c.host_flags = host_flags::kShutdown;
  c.sequence = 42;
  c.echo_controller_sequence = 0xFFFFFFFFu;
  c.echo_controller_time_ns = 123456789012ull;
  c.manipulators[0].force_D_N = {0.25f, -19.0f, 3.5f};
  c.manipulators[0].flags = command_flags::kForceEnable | command_flags::kLimited;
  c.manipulators[1].force_D_N = {-1.0f, 0.0f, 2.0f};
  c.manipulators[1].flags = command_flags::kRamping;
  return c;
}

StatusBytes Encoded(const StatusFrame& f) {
  StatusBytes b{};
  EncodeStatusFrame(f, b);
  return b;
}

CommandBytes Encoded(const CommandFrame& c) {
  CommandBytes b{};
  EncodeCommandFrame(c, b);
  return b;
}

void ExpectSame(const StatusFrame& a, const StatusFrame& b) {
  EXPECT_EQ(a.controller_flags, b.controller_flags);
  EXPECT_EQ(a.sequence, b.sequence);
  EXPECT_EQ(a.echo_host_sequence, b.echo_host_sequence);
  EXPECT_EQ(a.controller_time_ns, b.controller_time_ns);
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    EXPECT_EQ(a.manipulators[i].p_D_m, b.manipulators[i].p_D_m);
    EXPECT_EQ(a.manipulators[i].q_DF.coeffs(), b.manipulators[i].q_DF.coeffs());
    EXPECT_EQ(a.manipulators[i].force_D_N, b.manipulators[i].force_D_N);
    EXPECT_EQ(a.manipulators[i].flags, b.manipulators[i].flags);
  }
}

std::uint32_t ReadU32(const std::byte* p) {
  return std::to_integer<std::uint32_t>(p[0]) | std::to_integer<std::uint32_t>(p[1]) << 8 |
         std::to_integer<std::uint32_t>(p[2]) << 16 | std::to_integer<std::uint32_t>(p[3]) << 24;
}

// Re-computes the checksum after a test edited the bytes, so the value checks are reached.
template <std::size_t N>
void Reseal(std::array<std::byte, N>* b) {
  const std::uint32_t crc = Crc32c(std::span<const std::byte>(b->data(), N - 4));
  for (int i = 0; i < 4; ++i) (*b)[N - 4 + i] = static_cast<std::byte>((crc >> (8 * i)) & 0xFF);
}

FrameError DecodeStatus(std::span<const std::byte> bytes) {
  StatusFrame out;
  return DecodeStatusFrame(bytes, GrabValueLimits{}, &out);
}

TEST(GrabProtocolTest, StatusRoundTrip) {
  const StatusFrame in = SampleStatus();
  const StatusBytes bytes = Encoded(in);
  StatusFrame out;
  ASSERT_EQ(DecodeStatusFrame(bytes, GrabValueLimits{}, &out), FrameError::kNone);
  ExpectSame(in, out);
}

TEST(GrabProtocolTest, CommandRoundTrip) {
  const CommandFrame in = SampleCommand();
  const CommandBytes bytes = Encoded(in);
  CommandFrame out;
  ASSERT_EQ(DecodeCommandFrame(bytes, GrabValueLimits{}, &out), FrameError::kNone);
  EXPECT_EQ(out.host_flags, in.host_flags);
  EXPECT_EQ(out.sequence, in.sequence);
  EXPECT_EQ(out.echo_controller_sequence, in.echo_controller_sequence);
  EXPECT_EQ(out.echo_controller_time_ns, in.echo_controller_time_ns);
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    EXPECT_EQ(out.manipulators[i].force_D_N, in.manipulators[i].force_D_N);
    EXPECT_EQ(out.manipulators[i].flags, in.manipulators[i].flags);
  }
}

TEST(GrabProtocolTest, WireLayoutMatchesTheDocument) {
  const StatusBytes s = Encoded(SampleStatus());
  // "GRBS", version 1, flags, little-endian sequence at offset 8
  EXPECT_EQ(s[0], std::byte{'G'});
  EXPECT_EQ(s[1], std::byte{'R'});
  EXPECT_EQ(s[2], std::byte{'B'});
  EXPECT_EQ(s[3], std::byte{'S'});
  EXPECT_EQ(s[4], std::byte{1});
  EXPECT_EQ(s[5], std::byte{0});
  EXPECT_EQ(s[6], std::byte{controller_flags::kCommandRejected});
  EXPECT_EQ(s[8], std::byte{0xD4});
  EXPECT_EQ(s[11], std::byte{0xA1});
  EXPECT_EQ(ReadU32(&s[12]), 77u);
  EXPECT_EQ(s[16], std::byte{0x08});
  EXPECT_EQ(s[23], std::byte{0x01});
  // thumb z position at 24 + 8, index force z at 68 + 36, index flags at 68 + 40
  EXPECT_EQ(ReadU32(&s[32]), std::bit_cast<std::uint32_t>(0.056f));
  EXPECT_EQ(ReadU32(&s[104]), std::bit_cast<std::uint32_t>(-19.5f));
  EXPECT_EQ(s[108], std::byte{manipulator_flags::kCalibrated | manipulator_flags::kWorkspaceLimit});
  EXPECT_EQ(ReadU32(&s[112]), Crc32c(std::span<const std::byte>(s.data(), 112)));

  const CommandBytes c = Encoded(SampleCommand());
  EXPECT_EQ(c[3], std::byte{'C'});
  EXPECT_EQ(ReadU32(&c[8]), 42u);
  EXPECT_EQ(ReadU32(&c[12]), 0xFFFFFFFFu);
  EXPECT_EQ(ReadU32(&c[28]), std::bit_cast<std::uint32_t>(-19.0f));  // thumb force y
  EXPECT_EQ(c[52], std::byte{command_flags::kRamping});              // index flags
  EXPECT_EQ(ReadU32(&c[56]), Crc32c(std::span<const std::byte>(c.data(), 56)));
}

// The example frames of docs/grab-protocol.md section 10, byte for byte: the thumb on the user's
// side (+y in D, as in W under the identity X_WD), its pad facing the index through the fabric,
// pushed back towards the user by the fabric it presses.
TEST(GrabProtocolTest, DocumentExampleFrames) {
  StatusFrame f;
  f.sequence = 1000;
  f.echo_host_sequence = 998;
  f.controller_time_ns = 200000000;
  f.manipulators[0].p_D_m = {0.0f, 0.03f, 0.0f};
  f.manipulators[0].q_DF = Eigen::Quaternionf(0.70710678f, 0.70710678f, 0.0f, 0.0f);
  f.manipulators[0].force_D_N = {0.0f, 1.5f, 0.0f};
  f.manipulators[0].flags = manipulator_flags::kCalibrated | manipulator_flags::kForceEnabled;
  f.manipulators[1].p_D_m = {0.0f, -0.03f, 0.0f};
  f.manipulators[1].q_DF = Eigen::Quaternionf(0.70710678f, -0.70710678f, 0.0f, 0.0f);
  f.manipulators[1].flags = manipulator_flags::kCalibrated;
  // the geometry the document describes: each pad (+z_F) faces the other finger, and the force on
  // the thumb pushes it out of the fabric, against its pad normal
  const Eigen::Vector3f thumb_to_index = f.manipulators[1].p_D_m - f.manipulators[0].p_D_m;
  const Eigen::Vector3f thumb_pad_D = f.manipulators[0].q_DF * Eigen::Vector3f::UnitZ();
  const Eigen::Vector3f index_pad_D = f.manipulators[1].q_DF * Eigen::Vector3f::UnitZ();
  EXPECT_TRUE(thumb_pad_D.isApprox(-Eigen::Vector3f::UnitY(), 1e-6f));
  EXPECT_GT(thumb_pad_D.dot(thumb_to_index), 0.0f);
  EXPECT_GT(index_pad_D.dot(-thumb_to_index), 0.0f);
  EXPECT_LT(f.manipulators[0].force_D_N.dot(thumb_pad_D), 0.0f);
  const std::array<unsigned, kStatusFrameSize> status_hex = {
      0x47, 0x52, 0x42, 0x53, 0x01, 0x00, 0x00, 0x00, 0xe8, 0x03, 0x00, 0x00, 0xe6, 0x03, 0x00, 0x00, 0x00,
      0xc2, 0xeb, 0x0b, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x8f, 0xc2, 0xf5, 0x3c, 0x00, 0x00,
      0x00, 0x00, 0xf3, 0x04, 0x35, 0x3f, 0xf3, 0x04, 0x35, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xc0, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x8f, 0xc2, 0xf5, 0xbc, 0x00, 0x00, 0x00, 0x00, 0xf3, 0x04, 0x35, 0x3f, 0xf3,
      0x04, 0x35, 0xbf, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x68, 0x3e, 0x4c, 0x8f};
  const StatusBytes s = Encoded(f);
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_EQ(std::to_integer<unsigned>(s[i]), status_hex[i]) << i;

  CommandFrame c;
  c.sequence = 999;
  c.echo_controller_sequence = 1000;
  c.echo_controller_time_ns = 200000000;
  c.manipulators[0].force_D_N = {0.0f, 1.5f, 0.0f};
  c.manipulators[0].flags = command_flags::kForceEnable;
  c.manipulators[1].flags = command_flags::kForceEnable;
  EXPECT_LT(c.manipulators[0].force_D_N.dot(thumb_pad_D), 0.0f) << "the command pushes the thumb out too";
  const std::array<unsigned, kCommandFrameSize> command_hex = {
      0x47, 0x52, 0x42, 0x43, 0x01, 0x00, 0x00, 0x00, 0xe7, 0x03, 0x00, 0x00, 0xe8, 0x03, 0x00,
      0x00, 0x00, 0xc2, 0xeb, 0x0b, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0xc0, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x72, 0x71, 0x89, 0x14};
  const CommandBytes cb = Encoded(c);
  for (std::size_t i = 0; i < cb.size(); ++i) EXPECT_EQ(std::to_integer<unsigned>(cb[i]), command_hex[i]) << i;
}

TEST(GrabProtocolTest, RejectsShortAndLong) {
  const StatusBytes good = Encoded(SampleStatus());
  EXPECT_EQ(DecodeStatus({}), FrameError::kTooShort);
  EXPECT_EQ(DecodeStatus(std::span(good).first(5)), FrameError::kTooShort);
  EXPECT_EQ(DecodeStatus(std::span(good).first(kStatusFrameSize - 1)), FrameError::kTooShort);
  std::array<std::byte, kStatusFrameSize + 1> longer{};
  std::copy(good.begin(), good.end(), longer.begin());
  EXPECT_EQ(DecodeStatus(longer), FrameError::kTooLong);
}

TEST(GrabProtocolTest, RejectsBadMagicVersionAndChecksum) {
  StatusBytes b = Encoded(SampleStatus());
  b[0] = std::byte{'X'};
  EXPECT_EQ(DecodeStatus(b), FrameError::kBadMagic);

  b = Encoded(SampleStatus());
  b[4] = std::byte{2};
  EXPECT_EQ(DecodeStatus(b), FrameError::kBadVersion);

  b = Encoded(SampleStatus());
  b[50] ^= std::byte{0x10};
  EXPECT_EQ(DecodeStatus(b), FrameError::kBadChecksum);
  b = Encoded(SampleStatus());
  b[113] ^= std::byte{0x01};  // the checksum field itself
  EXPECT_EQ(DecodeStatus(b), FrameError::kBadChecksum);

  // a command fed to the status decoder (and the other way round) is a wrong magic
  const CommandBytes c = Encoded(SampleCommand());
  EXPECT_EQ(DecodeStatus(c), FrameError::kBadMagic);
  CommandFrame out;
  EXPECT_EQ(DecodeCommandFrame(Encoded(SampleStatus()), GrabValueLimits{}, &out), FrameError::kBadMagic);
}

TEST(GrabProtocolTest, RejectsNonFiniteValues) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  StatusFrame f = SampleStatus();
  f.manipulators[0].p_D_m.y() = nan;
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kNonFinite);
  f = SampleStatus();
  f.manipulators[1].q_DF.w() = nan;
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kNonFinite);
  f = SampleStatus();
  f.manipulators[1].force_D_N.x() = -inf;
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kNonFinite);

  CommandFrame c = SampleCommand();
  c.manipulators[1].force_D_N.z() = nan;
  CommandFrame out;
  EXPECT_EQ(DecodeCommandFrame(Encoded(c), GrabValueLimits{}, &out), FrameError::kNonFinite);
}

TEST(GrabProtocolTest, RejectsPositionOutsideTheWorkspace) {
  StatusFrame f = SampleStatus();
  f.manipulators[0].p_D_m.x() = 0.204f;  // inside the 5 mm margin
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kNone);
  f.manipulators[0].p_D_m.x() = 0.206f;
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kOutOfWorkspace);
  f = SampleStatus();
  f.manipulators[1].p_D_m.y() = -0.11f;  // depth is only 200 mm
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kOutOfWorkspace);
  f = SampleStatus();
  f.manipulators[1].p_D_m.z() = 0.16f;  // height 300 mm
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kOutOfWorkspace);
}

TEST(GrabProtocolTest, RejectsNonUnitQuaternion) {
  StatusFrame f = SampleStatus();
  f.manipulators[0].q_DF.coeffs() *= 1.01f;
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kBadQuaternion);
  f.manipulators[0].q_DF.coeffs().setZero();
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kBadQuaternion);
}

TEST(GrabProtocolTest, RejectsInsaneForces) {
  StatusFrame f = SampleStatus();
  f.manipulators[1].force_D_N = {0.0f, 61.0f, 0.0f};
  EXPECT_EQ(DecodeStatus(Encoded(f)), FrameError::kForceOutOfRange);
  CommandFrame c = SampleCommand();
  c.manipulators[0].force_D_N = {20.0f, 20.0f, 0.0f};
  CommandFrame out;
  EXPECT_EQ(DecodeCommandFrame(Encoded(c), GrabValueLimits{}, &out), FrameError::kForceOutOfRange);
}

TEST(GrabProtocolTest, RejectedFrameLeavesOutputUntouched) {
  StatusFrame out = SampleStatus();
  StatusBytes b = Encoded(StatusFrame{});
  b[60] ^= std::byte{1};
  ASSERT_EQ(DecodeStatusFrame(b, GrabValueLimits{}, &out), FrameError::kBadChecksum);
  ExpectSame(out, SampleStatus());
}

TEST(GrabProtocolTest, CountersPerReason) {
  FrameCounters counters;
  counters.Add(FrameError::kNone);
  counters.Add(FrameError::kBadChecksum);
  counters.Add(FrameError::kBadChecksum);
  counters.Add(FrameError::kTooShort);
  EXPECT_EQ(counters.accepted(), 1u);
  EXPECT_EQ(counters.Get(FrameError::kBadChecksum), 2u);
  EXPECT_EQ(counters.TotalRejected(), 3u);
  for (std::size_t i = 0; i < kFrameErrorCount; ++i) {
    EXPECT_NE(FrameErrorName(static_cast<FrameError>(i)), "invalid");
  }
}

TEST(GrabProtocolTest, SequenceComparisonWraps) {
  EXPECT_TRUE(SequenceNewer(2, 1));
  EXPECT_FALSE(SequenceNewer(1, 2));
  EXPECT_FALSE(SequenceNewer(5, 5));
  EXPECT_TRUE(SequenceNewer(0, 0xFFFFFFFFu));
  EXPECT_TRUE(SequenceNewer(3, 0xFFFFFFF0u));
}

// 0 means "none" in the echo fields, so no frame carries it: the wrap goes from 2^32 - 1 to 1,
// and the comparison still orders across it.
TEST(GrabProtocolTest, NextSequenceSkipsZero) {
  EXPECT_EQ(NextSequence(0), 1u);
  EXPECT_EQ(NextSequence(41), 42u);
  EXPECT_EQ(NextSequence(0xFFFFFFFFu), 1u);
  EXPECT_TRUE(SequenceNewer(NextSequence(0xFFFFFFFFu), 0xFFFFFFFFu));
}

// Random datagrams (any length, random bytes, random bytes behind a valid header, and valid
// frames with random corruption) never crash and are all rejected.
TEST(GrabProtocolTest, GarbageFloodIsRejected) {
  DeterministicRng rng(12345);
  const StatusBytes good_status = Encoded(SampleStatus());
  const CommandBytes good_command = Encoded(SampleCommand());
  std::array<std::byte, 256> buffer{};
  FrameCounters status_counters;
  FrameCounters command_counters;
  constexpr int kDatagrams = 200000;
  for (int n = 0; n < kDatagrams; ++n) {
    const int kind = n % 4;
    const std::size_t length = kind == 1   ? kStatusFrameSize
                               : kind == 2 ? kCommandFrameSize
                                           : rng.Next() % buffer.size();
    for (std::size_t i = 0; i < length; ++i) buffer[i] = static_cast<std::byte>(rng.Next() & 0xFF);
    if (kind == 1 || kind == 2) {
      // a valid header so decoding goes as far as the checksum
      const std::span<const std::byte> header = kind == 1 ? std::span<const std::byte>(good_status).first(6)
                                                          : std::span<const std::byte>(good_command).first(6);
      std::copy(header.begin(), header.end(), buffer.begin());
    } else if (kind == 3) {
      // a valid frame with 1 to 8 random bit flips, at its own length
      const bool status = (n / 4) % 2 == 0;
      const std::span<const std::byte> frame =
          status ? std::span<const std::byte>(good_status) : std::span<const std::byte>(good_command);
      std::copy(frame.begin(), frame.end(), buffer.begin());
      const std::size_t flips = 1 + rng.Next() % 8;
      for (std::size_t k = 0; k < flips; ++k) {
        const std::size_t bit = rng.Next() % (frame.size() * 8);
        buffer[bit / 8] ^= static_cast<std::byte>(1u << (bit % 8));
      }
      // flips may cancel out: skip the rare exact copy
      if (std::equal(frame.begin(), frame.end(), buffer.begin())) continue;
      StatusFrame s;
      CommandFrame c;
      const std::span<const std::byte> d(buffer.data(), frame.size());
      status_counters.Add(DecodeStatusFrame(d, GrabValueLimits{}, &s));
      command_counters.Add(DecodeCommandFrame(d, GrabValueLimits{}, &c));
      continue;
    }
    StatusFrame s;
    CommandFrame c;
    const std::span<const std::byte> d(buffer.data(), length);
    status_counters.Add(DecodeStatusFrame(d, GrabValueLimits{}, &s));
    command_counters.Add(DecodeCommandFrame(d, GrabValueLimits{}, &c));
  }
  EXPECT_EQ(status_counters.accepted(), 0u);
  EXPECT_EQ(command_counters.accepted(), 0u);
  EXPECT_GT(status_counters.Get(FrameError::kBadChecksum), 0u);
  EXPECT_GT(status_counters.Get(FrameError::kTooShort), 0u);
  EXPECT_GT(status_counters.Get(FrameError::kBadMagic), 0u);
  EXPECT_GT(command_counters.Get(FrameError::kBadChecksum), 0u);
}

TEST(GrabProtocolTest, EncodeAndDecodeDoNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  const StatusFrame in = SampleStatus();
  StatusBytes bytes{};
  StatusFrame out;
  CommandBytes cbytes{};
  CommandFrame cout;
  testing::AllocationCounter counter;
  EncodeStatusFrame(in, bytes);
  const FrameError e = DecodeStatusFrame(bytes, GrabValueLimits{}, &out);
  EncodeCommandFrame(SampleCommand(), cbytes);
  const FrameError ce = DecodeCommandFrame(cbytes, GrabValueLimits{}, &cout);
  EXPECT_EQ(counter.count(), 0);
  EXPECT_EQ(e, FrameError::kNone);
  EXPECT_EQ(ce, FrameError::kNone);
}

}  // namespace
}  // namespace haptex::device
