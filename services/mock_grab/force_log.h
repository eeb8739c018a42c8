#pragma once
// What the mock's fingers felt, written to CSV off the 5 kHz loop: the loop pushes samples into a
// ring, a writer thread drains it to the file.
//
// time_ns (CLOCK_MONOTONIC, comparable across processes on one machine), then per finger (thumb,
// index) the commanded and the applied force in frame D [N], then host_timed_out and the
// sequence of the host command in force (0 before the first).

#include <atomic>
#include <cstdint>
#include <fstream>
#include <string>
#include <thread>

#include "libs/runtime/spsc_ring.h"

namespace haptex::mock_grab {

struct ForceSample {
  std::int64_t time_ns = 0;
  float commanded_N[2][3] = {};
  float applied_N[2][3] = {};
  bool host_timed_out = false;
  std::uint32_t host_sequence = 0;
};

class ForceLog {
 public:
  /// Throws std::runtime_error when the file cannot be written.
  explicit ForceLog(const std::string& path);
  ~ForceLog();  // drains everything left, then closes
  ForceLog(const ForceLog&) = delete;
  ForceLog& operator=(const ForceLog&) = delete;

  /// Loop side: never blocks or allocates; a full ring drops (and counts) the sample.
  void Push(const ForceSample& sample);
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  void WriteWaiting();

  std::ofstream out_;
  runtime::SpscRing<ForceSample, 16384> ring_;
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<bool> stop_{false};
  std::thread writer_;
};

}  // namespace haptex::mock_grab
