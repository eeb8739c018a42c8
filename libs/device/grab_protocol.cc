#include "libs/device/grab_protocol.h"

#include <bit>
#include <cmath>

#include "libs/device/crc32c.h"

namespace haptex::device {
namespace {

// Explicit little-endian packing: the wire layout never depends on the host's struct layout or
// byte order.
class Writer {
 public:
  explicit Writer(std::span<std::byte> out) : out_(out) {}
  void U16(std::uint16_t v) { Bytes(v, 2); }
  void U32(std::uint32_t v) { Bytes(v, 4); }
  void U64(std::uint64_t v) { Bytes(v, 8); }
  void F32(float v) { U32(std::bit_cast<std::uint32_t>(v)); }
  void Vec3(const Eigen::Vector3f& v) {
    F32(v.x());
    F32(v.y());
    F32(v.z());
  }
  std::size_t offset() const { return offset_; }

 private:
  void Bytes(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_[offset_++] = static_cast<std::byte>((v >> (8 * i)) & 0xFFu);
  }
  std::span<std::byte> out_;
  std::size_t offset_ = 0;
};

class Reader {
 public:
  explicit Reader(std::span<const std::byte> in, std::size_t offset = 0) : in_(in), offset_(offset) {}
  std::uint16_t U16() { return static_cast<std::uint16_t>(Bytes(2)); }
  std::uint32_t U32() { return static_cast<std::uint32_t>(Bytes(4)); }
  std::uint64_t U64() { return Bytes(8); }
  float F32() { return std::bit_cast<float>(U32()); }
  Eigen::Vector3f Vec3() {
    const float x = F32();
    const float y = F32();
    const float z = F32();
    return {x, y, z};
  }

 private:
  std::uint64_t Bytes(int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::to_integer<std::uint64_t>(in_[offset_++]) << (8 * i);
    return v;
  }
  std::span<const std::byte> in_;
  std::size_t offset_;
};

constexpr std::size_t kChecksumSize = 4;

void WriteChecksum(std::span<std::byte> frame) {
  const std::size_t body = frame.size() - kChecksumSize;
  Writer w(frame.subspan(body));
  w.U32(Crc32c(frame.first(body)));
}

// Common header checks: length, magic, version, checksum (in the documented order).
FrameError CheckEnvelope(std::span<const std::byte> d, std::uint32_t magic, std::size_t size) {
  if (d.size() < 6) return FrameError::kTooShort;
  Reader r(d);
  if (r.U32() != magic) return FrameError::kBadMagic;
  if (r.U16() != kGrabProtocolVersion) return FrameError::kBadVersion;
  if (d.size() < size) return FrameError::kTooShort;
  if (d.size() > size) return FrameError::kTooLong;
  const std::size_t body = size - kChecksumSize;
  if (Reader(d, body).U32() != Crc32c(d.first(body))) return FrameError::kBadChecksum;
  return FrameError::kNone;
}

bool AllFinite(const Eigen::Vector3f& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

FrameError CheckManipulator(const ManipulatorStatus& m, const GrabValueLimits& limits) {
  if (!AllFinite(m.p_D_m) || !AllFinite(m.force_D_N) || !std::isfinite(m.q_DF.w()) || !AllFinite(m.q_DF.vec())) {
    return FrameError::kNonFinite;
  }
  const Eigen::Vector3f bound = limits.workspace_half_extent_m.array() + limits.workspace_margin_m;
  if ((m.p_D_m.cwiseAbs().array() > bound.array()).any()) return FrameError::kOutOfWorkspace;
  if (std::abs(m.q_DF.norm() - 1.0f) > limits.quaternion_norm_tolerance) {
    return FrameError::kBadQuaternion;
  }
  if (m.force_D_N.norm() > limits.max_measured_force_N) return FrameError::kForceOutOfRange;
  return FrameError::kNone;
}

}  // namespace

std::string_view FrameErrorName(FrameError error) {
  switch (error) {
    case FrameError::kNone:
      return "accepted";
    case FrameError::kTooShort:
      return "too_short";
    case FrameError::kTooLong:
      return "too_long";
    case FrameError::kBadMagic:
      return "bad_magic";
    case FrameError::kBadVersion:
      return "bad_version";
    case FrameError::kBadChecksum:
      return "bad_checksum";
    case FrameError::kNonFinite:
      return "non_finite";
    case FrameError::kOutOfWorkspace:
      return "out_of_workspace";
    case FrameError::kBadQuaternion:
      return "bad_quaternion";
    case FrameError::kForceOutOfRange:
      return "force_out_of_range";
    case FrameError::kCount:
      break;
  }
  return "invalid";
}

std::uint64_t FrameCounters::TotalRejected() const {
  std::uint64_t total = 0;
  for (std::size_t i = 1; i < kFrameErrorCount; ++i) total += counts_[i];
  return total;
}

void EncodeStatusFrame(const StatusFrame& frame, std::span<std::byte, kStatusFrameSize> out) {
  Writer w(out);
  w.U32(kStatusMagic);
  w.U16(kGrabProtocolVersion);
  w.U16(frame.controller_flags);
  w.U32(frame.sequence);
  w.U32(frame.echo_host_sequence);
  w.U64(frame.controller_time_ns);
  for (const ManipulatorStatus& m : frame.manipulators) {
    w.Vec3(m.p_D_m);
    w.F32(m.q_DF.w());
    w.F32(m.q_DF.x());
    w.F32(m.q_DF.y());
    w.F32(m.q_DF.z());
    w.Vec3(m.force_D_N);
    w.U16(m.flags);
    w.U16(0);  // reserved
  }
  WriteChecksum(out);
}

void EncodeCommandFrame(const CommandFrame& frame, std::span<std::byte, kCommandFrameSize> out) {
  Writer w(out);
  w.U32(kCommandMagic);
  w.U16(kGrabProtocolVersion);
  w.U16(frame.host_flags);
  w.U32(frame.sequence);
  w.U32(frame.echo_controller_sequence);
  w.U64(frame.echo_controller_time_ns);
  for (const ManipulatorCommand& m : frame.manipulators) {
    w.Vec3(m.force_D_N);
    w.U16(m.flags);
    w.U16(0);  // reserved
  }
  WriteChecksum(out);
}

FrameError DecodeStatusFrame(std::span<const std::byte> datagram, const GrabValueLimits& limits, StatusFrame* out) {
  if (const FrameError e = CheckEnvelope(datagram, kStatusMagic, kStatusFrameSize); e != FrameError::kNone) {
    return e;
  }
  StatusFrame f;
  Reader r(datagram, 6);
  f.controller_flags = r.U16();
  f.sequence = r.U32();
  f.echo_host_sequence = r.U32();
  f.controller_time_ns = r.U64();
  for (ManipulatorStatus& m : f.manipulators) {
    m.p_D_m = r.Vec3();
    const float qw = r.F32();
    const float qx = r.F32();
    const float qy = r.F32();
    const float qz = r.F32();
    m.q_DF = Eigen::Quaternionf(qw, qx, qy, qz);
    m.force_D_N = r.Vec3();
    m.flags = r.U16();
    r.U16();  // reserved: ignored by receivers
    if (const FrameError e = CheckManipulator(m, limits); e != FrameError::kNone) return e;
  }
  *out = f;
  return FrameError::kNone;
}

FrameError DecodeCommandFrame(std::span<const std::byte> datagram, const GrabValueLimits& limits, CommandFrame* out) {
  if (const FrameError e = CheckEnvelope(datagram, kCommandMagic, kCommandFrameSize); e != FrameError::kNone) {
    return e;
  }
  CommandFrame f;
  Reader r(datagram, 6);
  f.host_flags = r.U16();
  f.sequence = r.U32();
  f.echo_controller_sequence = r.U32();
  f.echo_controller_time_ns = r.U64();
  for (ManipulatorCommand& m : f.manipulators) {
    m.force_D_N = r.Vec3();
    m.flags = r.U16();
    r.U16();  // reserved
    if (!AllFinite(m.force_D_N)) return FrameError::kNonFinite;
    if (m.force_D_N.norm() > limits.max_command_force_N) return FrameError::kForceOutOfRange;
  }
  *out = f;
  return FrameError::kNone;
}

}  // namespace haptex::device
