#pragma once
// Recorded fingertip trajectories for the mock controller's playback script.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace haptex::device {

/// One sample of a recorded trajectory, device workspace frame D.
struct TrajectorySample {
  double t_s = 0.0;
  Eigen::Vector3d thumb_D_m{Eigen::Vector3d::Zero()};
  Eigen::Vector3d index_D_m{Eigen::Vector3d::Zero()};
};

/// The header line a trajectory CSV must start with (after comments and blank lines).
inline constexpr std::string_view kTrajectoryCsvHeader =
    "t_s,thumb_x_m,thumb_y_m,thumb_z_m,index_x_m,index_y_m,index_z_m";

/// Parses a trajectory CSV: the header above, then one row of 7 finite numbers per sample with
/// strictly increasing t_s, at least 2 rows. Lines starting with '#' and blank lines are skipped;
/// '\r\n' line ends are accepted.
/// @throws std::invalid_argument naming the line and the problem ("line 5: expected 7 fields,
///         got 6").
std::vector<TrajectorySample> ParseTrajectoryCsv(std::string_view text);

/// The largest trajectory file read (about 20 hours of samples at 1 kHz).
inline constexpr std::uintmax_t kMaxTrajectoryCsvBytes = std::uintmax_t{64} << 20;

/// Reads and parses a regular file of at most kMaxTrajectoryCsvBytes. @throws std::invalid_argument
/// (not a regular file, too large, unreadable or bad content; the message starts with the path).
std::vector<TrajectorySample> LoadTrajectoryCsv(const std::string& path);

}  // namespace haptex::device
