#include "libs/runtime/rt_event_log.h"

#include <spdlog/spdlog.h>

#include <chrono>

#include "libs/base/clock.h"

namespace haptex::runtime {

void RtEventLog::Push(RtLogLevel level, const char* message, double value) {
  if (!ring_.TryPush(RtEvent{level, message, value, base::SteadyNowNs()})) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
  }
}

std::size_t RtEventLog::Flush(spdlog::logger& logger) {
  std::size_t flushed = 0;
  RtEvent event;
  while (ring_.TryPop(&event)) {
    const auto level = event.level == RtLogLevel::kDebug  ? spdlog::level::debug
                       : event.level == RtLogLevel::kInfo ? spdlog::level::info
                       : event.level == RtLogLevel::kWarn ? spdlog::level::warn
                                                          : spdlog::level::err;
    logger.log(level, "{} {}", event.message, event.value);
    ++flushed;
  }
  return flushed;
}

LogFlusher::LogFlusher(RtEventLog* log, std::shared_ptr<spdlog::logger> logger, int period_ms)
    : log_(log), logger_(std::move(logger)) {
  thread_ = std::thread([this, period_ms] {
    while (!stop_.load(std::memory_order_acquire)) {
      log_->Flush(*logger_);
      std::this_thread::sleep_for(std::chrono::milliseconds(period_ms));
    }
    log_->Flush(*logger_);
  });
}

LogFlusher::~LogFlusher() {
  stop_.store(true, std::memory_order_release);
  thread_.join();
}

}  // namespace haptex::runtime
