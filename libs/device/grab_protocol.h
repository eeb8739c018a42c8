#pragma once
// The GRAB controller protocol: fixed-layout little-endian datagrams between the 5 kHz force
// controller and the host (device_bridge). docs/grab-protocol.md is the normative description;
// this file implements exactly that table and nothing else.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace haptex::device {

inline constexpr std::uint16_t kGrabProtocolVersion = 1;
/// "GRBS" in wire byte order (bytes 0x47 0x52 0x42 0x53).
inline constexpr std::uint32_t kStatusMagic = 0x53425247u;
/// "GRBC" in wire byte order (bytes 0x47 0x52 0x42 0x43).
inline constexpr std::uint32_t kCommandMagic = 0x43425247u;
inline constexpr std::size_t kStatusFrameSize = 116;
inline constexpr std::size_t kCommandFrameSize = 60;
/// Nominal controller rate: one StatusFrame per control tick.
inline constexpr double kControllerRate_Hz = 5000.0;
/// The rates either side may run at (docs/grab-protocol.md section 1): at 1 kHz a command is at
/// most 1 ms old, well inside the controller's 5 ms host timeout and the bridge's 4 ms stall limit.
inline constexpr double kMinGrabRate_Hz = 1000.0;
inline constexpr double kMaxGrabRate_Hz = 20000.0;
inline constexpr std::size_t kManipulatorCount = 2;

/// Manipulator slot on the wire: slot 0 is the thumb, slot 1 the index finger.
enum class Manipulator : std::uint8_t { kThumb = 0, kIndex = 1 };

/// Controller-wide status bits (StatusFrame offset 6).
namespace controller_flags {
inline constexpr std::uint16_t kEmergencyStop = 1u << 0;    // e-stop engaged, forces off
inline constexpr std::uint16_t kHostTimeout = 1u << 1;      // no valid command for 5 ms: zero force
inline constexpr std::uint16_t kCommandRejected = 1u << 2;  // a host datagram was rejected since last frame
}  // namespace controller_flags

/// Per-manipulator status bits (StatusFrame manipulator offset +40).
namespace manipulator_flags {
inline constexpr std::uint16_t kCalibrated = 1u << 0;        // homed: pose is valid
inline constexpr std::uint16_t kForceEnabled = 1u << 1;      // amplifiers on, tracking the command
inline constexpr std::uint16_t kForceSaturated = 1u << 2;    // command not reachable here
inline constexpr std::uint16_t kWorkspaceLimit = 1u << 3;    // at a mechanical limit
inline constexpr std::uint16_t kForceSensorFault = 1u << 4;  // measured force invalid (sent as 0)
inline constexpr std::uint16_t kOverTemperature = 1u << 5;   // thermal derating active
}  // namespace manipulator_flags

/// Host-wide command bits (CommandFrame offset 6).
namespace host_flags {
inline constexpr std::uint16_t kShutdown = 1u << 0;  // host stops sending: go to zero, no timeout fault
}  // namespace host_flags

/// Per-manipulator command bits (CommandFrame manipulator offset +12).
namespace command_flags {
inline constexpr std::uint16_t kForceEnable = 1u << 0;  // apply desired force; clear: zero force
inline constexpr std::uint16_t kRamping = 1u << 1;      // host ramp in (from zero) or out; only with kForceEnable
inline constexpr std::uint16_t kLimited = 1u << 2;      // host clamped this force (peak/continuous/slew)
}  // namespace command_flags

/// One manipulator as reported by the controller. Frame D: the device workspace frame.
struct ManipulatorStatus {
  Eigen::Vector3f p_D_m{Eigen::Vector3f::Zero()};           ///< contact part position [m]
  Eigen::Quaternionf q_DF{Eigen::Quaternionf::Identity()};  ///< contact-part frame F to D
  Eigen::Vector3f force_D_N{Eigen::Vector3f::Zero()};       ///< measured force on the fingertip [N]
  std::uint16_t flags = 0;                                  ///< manipulator_flags
};

/// Controller -> host datagram (kStatusFrameSize bytes on the wire).
struct StatusFrame {
  std::uint16_t controller_flags = 0;
  std::uint32_t sequence = 0;            ///< NextSequence per frame, never 0
  std::uint32_t echo_host_sequence = 0;  ///< last accepted CommandFrame.sequence, 0 if none
  std::uint64_t controller_time_ns = 0;  ///< controller monotonic clock
  std::array<ManipulatorStatus, kManipulatorCount> manipulators{};
};

/// One manipulator's command. Frame D.
struct ManipulatorCommand {
  Eigen::Vector3f force_D_N{Eigen::Vector3f::Zero()};  ///< desired force on the fingertip [N]
  std::uint16_t flags = 0;                             ///< command_flags
};

/// Host -> controller datagram (kCommandFrameSize bytes on the wire).
struct CommandFrame {
  std::uint16_t host_flags = 0;
  std::uint32_t sequence = 0;                  ///< NextSequence per frame starting at 1, never 0
  std::uint32_t echo_controller_sequence = 0;  ///< StatusFrame.sequence this force was computed from, 0 if none
  std::uint64_t echo_controller_time_ns = 0;   ///< StatusFrame.controller_time_ns of that frame
  std::array<ManipulatorCommand, kManipulatorCount> manipulators{};
};

/// Why a datagram was rejected (kNone: accepted). Checks run in the order of
/// docs/grab-protocol.md section 6: length >= 6, magic, version, exact length, checksum, values.
enum class FrameError : std::uint8_t {
  kNone = 0,
  kTooShort,         // fewer bytes than the frame (or than magic + version)
  kTooLong,          // more bytes than the frame
  kBadMagic,         // not this frame type
  kBadVersion,       // another protocol version
  kBadChecksum,      // CRC-32C mismatch: corrupted in transit
  kNonFinite,        // NaN or Inf in a float field
  kOutOfWorkspace,   // position outside the workspace box plus margin
  kBadQuaternion,    // orientation not a unit quaternion
  kForceOutOfRange,  // force magnitude above the sane limit
  kCount
};

inline constexpr std::size_t kFrameErrorCount = static_cast<std::size_t>(FrameError::kCount);

/// Stable lower_snake_case name for Health and summaries.
std::string_view FrameErrorName(FrameError error);

/// One counter per FrameError (kNone counts accepted frames).
class FrameCounters {
 public:
  void Add(FrameError error) { ++counts_[static_cast<std::size_t>(error)]; }
  std::uint64_t Get(FrameError error) const { return counts_[static_cast<std::size_t>(error)]; }
  std::uint64_t accepted() const { return Get(FrameError::kNone); }
  std::uint64_t TotalRejected() const;

 private:
  std::array<std::uint64_t, kFrameErrorCount> counts_{};
};

/// Value checks applied when decoding. Defaults match docs/grab-protocol.md.
struct GrabValueLimits {
  /// Half extents of the workspace box centred on D's origin: 400 x 200 x 300 mm (x, y, z).
  Eigen::Vector3f workspace_half_extent_m{0.200f, 0.100f, 0.150f};
  float workspace_margin_m = 0.005f;        ///< tolerance outside the box (sensor overshoot)
  float quaternion_norm_tolerance = 1e-3f;  ///< accept | |q| - 1 | <= this
  float max_measured_force_N = 60.0f;       ///< 3x device peak: above this the sensor is broken
  float max_command_force_N = 25.0f;        ///< controller clamps to 20 N; above 25 N is corrupt
};

/// Writes `frame` into exactly kStatusFrameSize bytes, computing the checksum. Never fails: values
/// are not checked (so tests can build bad frames with valid checksums).
void EncodeStatusFrame(const StatusFrame& frame, std::span<std::byte, kStatusFrameSize> out);
/// Writes `frame` into exactly kCommandFrameSize bytes, computing the checksum.
void EncodeCommandFrame(const CommandFrame& frame, std::span<std::byte, kCommandFrameSize> out);

/// Decodes and checks one datagram. On kNone `*out` holds the frame; otherwise `*out` is unchanged.
FrameError DecodeStatusFrame(std::span<const std::byte> datagram, const GrabValueLimits& limits, StatusFrame* out);
/// Decodes and checks one command datagram (used by controllers, including the mock).
FrameError DecodeCommandFrame(std::span<const std::byte> datagram, const GrabValueLimits& limits, CommandFrame* out);

/// Sequence comparison modulo 2^32 (RFC 1982 style): true if `a` is newer than `b`.
constexpr bool SequenceNewer(std::uint32_t a, std::uint32_t b) {
  return a != b && static_cast<std::uint32_t>(a - b) < 0x80000000u;
}

/// The sequence after `s`: +1, wrapping from 2^32 - 1 to 1. 0 is never sent, because it means
/// "none" in the echo fields; a receiver ignores a frame with sequence 0 (out of order).
constexpr std::uint32_t NextSequence(std::uint32_t s) { return s == 0xFFFFFFFFu ? 1u : s + 1u; }

}  // namespace haptex::device
