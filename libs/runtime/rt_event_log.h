#pragma once
// Logging for hot loops: the loop pushes small POD events into a ring (never blocks, never
// allocates); a LogFlusher thread (or any non-hot code) writes them through spdlog.

#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include "libs/runtime/spsc_ring.h"

namespace spdlog {
class logger;
}

namespace haptex::runtime {

enum class RtLogLevel : std::uint8_t { kDebug, kInfo, kWarn, kError };

struct RtEvent {
  RtLogLevel level = RtLogLevel::kInfo;
  const char* message = "";  // must be a string literal (static storage)
  double value = 0.0;        // printed after the message
  std::int64_t time_ns = 0;  // base::SteadyNowNs when pushed
};

class RtEventLog final {
 public:
  static constexpr std::size_t kCapacity = 1024;

  /// Hot-loop side. Drops (and counts) when the ring is full.
  void Push(RtLogLevel level, const char* message, double value = 0.0);
  /// Writes every waiting event to `logger`; returns how many. Not for hot loops.
  std::size_t Flush(spdlog::logger& logger);
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  SpscRing<RtEvent, kCapacity> ring_;
  std::atomic<std::uint64_t> dropped_{0};
};

/// A thread that flushes an RtEventLog every period until destroyed.
class LogFlusher final {
 public:
  LogFlusher(RtEventLog* log, std::shared_ptr<spdlog::logger> logger, int period_ms = 50);
  ~LogFlusher();
  LogFlusher(const LogFlusher&) = delete;
  LogFlusher& operator=(const LogFlusher&) = delete;

 private:
  RtEventLog* log_;
  std::shared_ptr<spdlog::logger> logger_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace haptex::runtime
