#pragma once
// Reads the mock controller's force log (device::ForceLogRow's format), whole or as it grows.

#include <cstddef>
#include <string>
#include <vector>

#include "libs/device/force_log_row.h"

namespace haptex::launch {

/// The rows appended to a force log since the last call. Only whole lines count: the mock's
/// writer thread appends every few milliseconds while a reader may look, and a killed mock leaves
/// a line cut short.
class ForceLogTail {
 public:
  explicit ForceLogTail(std::string path) : path_(std::move(path)) {}
  std::vector<device::ForceLogRow> Next();

 private:
  std::string path_;
  std::size_t offset_ = 0;
};

/// Every whole row of the log at `path` (empty when it cannot be read).
std::vector<device::ForceLogRow> ReadForceLogRows(const std::string& path);

}  // namespace haptex::launch
