#pragma once
// The real-time options every service accepts, applied at start-up: each refused request is a
// warning, never a failure, so unprivileged machines still run.

#include <string>
#include <vector>

namespace spdlog {
class logger;
}

namespace haptex::runtime {

struct RtOptions {
  int fifo_priority = 0;  // 0: normal scheduling; 1..99: SCHED_FIFO
  std::vector<int> cpus;  // empty: any CPU
  bool lock_memory = false;
};

/// Applies the options to the calling thread/process; logs what worked (info) and what was
/// refused (warn). Returns the number of refused requests.
int ApplyRtOptions(const RtOptions& options, spdlog::logger& logger);

}  // namespace haptex::runtime
