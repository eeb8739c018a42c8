#include "libs/runtime/protobuf_log_capture.h"

#include <google/protobuf/stubs/logging.h>

#include <atomic>

namespace haptex::runtime {
namespace {

std::atomic<std::uint64_t> g_captured{0};

void CountProtobufLog(google::protobuf::LogLevel level, const char*, int, const std::string&) {
  g_captured.fetch_add(1, std::memory_order_relaxed);
  // FATAL still aborts inside protobuf after the handler returns.
  (void)level;
}

}  // namespace

void CaptureProtobufLogs() { google::protobuf::SetLogHandler(&CountProtobufLog); }
std::uint64_t CapturedProtobufLogCount() { return g_captured.load(std::memory_order_relaxed); }

}  // namespace haptex::runtime
