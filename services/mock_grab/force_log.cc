#include "services/mock_grab/force_log.h"

#include <array>
#include <chrono>
#include <stdexcept>

namespace haptex::mock_grab {

ForceLog::ForceLog(const std::string& path) : out_(path) {
  if (!out_) throw std::runtime_error("cannot write force log " + path);
  out_ << device::kForceLogHeader << '\n';
  writer_ = std::thread([this] {
    while (!stop_.load(std::memory_order_acquire)) {
      WriteWaiting();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    WriteWaiting();
  });
}

ForceLog::~ForceLog() {
  stop_.store(true, std::memory_order_release);
  writer_.join();
  out_.flush();
}

void ForceLog::Push(const device::ForceLogRow& row) {
  if (!ring_.TryPush(row)) dropped_.fetch_add(1, std::memory_order_relaxed);
}

void ForceLog::WriteWaiting() {
  device::ForceLogRow row;
  std::array<char, device::kForceLogLineBytes> line{};
  while (ring_.TryPop(&row))
    out_.write(line.data(), static_cast<std::streamsize>(device::FormatForceLogRow(row, line)));
}

}  // namespace haptex::mock_grab
