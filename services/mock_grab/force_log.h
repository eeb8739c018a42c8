#pragma once
// What the mock's fingers felt, written to CSV off the 5 kHz loop (device::ForceLogRow's format):
// the loop pushes rows into a ring, a writer thread drains it to the file.

#include <atomic>
#include <cstdint>
#include <fstream>
#include <string>
#include <thread>

#include "libs/device/force_log_row.h"
#include "libs/runtime/spsc_ring.h"

namespace haptex::mock_grab {

class ForceLog {
 public:
  /// Throws std::runtime_error when the file cannot be written.
  explicit ForceLog(const std::string& path);
  ~ForceLog();  // drains everything left, then closes
  ForceLog(const ForceLog&) = delete;
  ForceLog& operator=(const ForceLog&) = delete;

  /// Loop side: never blocks or allocates; a full ring drops (and counts) the row.
  void Push(const device::ForceLogRow& row);
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  void WriteWaiting();

  std::ofstream out_;
  runtime::SpscRing<device::ForceLogRow, 16384> ring_;
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<bool> stop_{false};
  std::thread writer_;
};

}  // namespace haptex::mock_grab
