#pragma once
// One row of the mock controller's force log (haptex-mock-grab --force-log): what each finger
// felt in one controller step. One format for the writer (services/mock_grab/force_log) and the
// reader (launch/force_log_reader), so the columns are named once:
//
//   time_ns (CLOCK_MONOTONIC, comparable across processes on one machine), then per finger
//   (thumb, index) the commanded and the applied force in frame D [N], then host_timed_out and
//   the sequence of the host command in force (0 before the first), then each finger's position in
//   D [m] (so the energy the device put into a finger can be summed from the log).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace haptex::device {

struct ForceLogRow {
  std::int64_t time_ns = 0;
  /// [finger][axis], finger 0 thumb, 1 index; frame D [N].
  std::array<std::array<double, 3>, 2> commanded_D_N{};
  std::array<std::array<double, 3>, 2> applied_D_N{};
  bool host_timed_out = false;
  std::uint32_t host_sequence = 0;
  /// [finger][axis]; frame D [m].
  std::array<std::array<double, 3>, 2> position_D_m{};

  /// |commanded force| of finger 0 (thumb) or 1 (index) [N].
  double CommandedNormN(int finger) const;
};

inline constexpr std::string_view kForceLogHeader =
    "time_ns,thumb_cmd_x,thumb_cmd_y,thumb_cmd_z,thumb_applied_x,thumb_applied_y,thumb_applied_z,"
    "index_cmd_x,index_cmd_y,index_cmd_z,index_applied_x,index_applied_y,index_applied_z,"
    "host_timed_out,host_sequence,thumb_x,thumb_y,thumb_z,index_x,index_y,index_z";
inline constexpr int kForceLogColumns = 21;
/// Longest line FormatForceLogRow writes, with its newline.
inline constexpr std::size_t kForceLogLineBytes = 512;

/// Writes `row` as one CSV line with its newline into `out` (no allocation); returns its length.
std::size_t FormatForceLogRow(const ForceLogRow& row, std::span<char, kForceLogLineBytes> out);
/// Parses one data line (with or without its newline); false for the header, a line cut short
/// (the writer was killed mid-line) or anything else that is not a row.
bool ParseForceLogRow(std::string_view line, ForceLogRow* row);

}  // namespace haptex::device
