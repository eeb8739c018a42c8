#include "services/mock_grab/force_log.h"

#include <chrono>
#include <stdexcept>

namespace haptex::mock_grab {

ForceLog::ForceLog(const std::string& path) : out_(path) {
  if (!out_) throw std::runtime_error("cannot write force log " + path);
  out_ << "time_ns,thumb_cmd_x,thumb_cmd_y,thumb_cmd_z,thumb_applied_x,thumb_applied_y,thumb_applied_z,"
          "index_cmd_x,index_cmd_y,index_cmd_z,index_applied_x,index_applied_y,index_applied_z,"
          "host_timed_out,host_sequence\n";
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

void ForceLog::Push(const ForceSample& sample) {
  if (!ring_.TryPush(sample)) dropped_.fetch_add(1, std::memory_order_relaxed);
}

void ForceLog::WriteWaiting() {
  ForceSample s;
  while (ring_.TryPop(&s)) {
    out_ << s.time_ns;
    for (int f = 0; f < 2; ++f) {
      for (int k = 0; k < 3; ++k) out_ << ',' << s.commanded_N[f][k];
      for (int k = 0; k < 3; ++k) out_ << ',' << s.applied_N[f][k];
    }
    out_ << ',' << (s.host_timed_out ? 1 : 0) << ',' << s.host_sequence << '\n';
  }
}

}  // namespace haptex::mock_grab
