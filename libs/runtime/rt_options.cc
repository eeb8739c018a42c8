#include "libs/runtime/rt_options.h"

#include <spdlog/spdlog.h>

#include "libs/runtime/rt_setup.h"

namespace haptex::runtime {

int ApplyRtOptions(const RtOptions& options, spdlog::logger& logger) {
  int refused = 0;
  auto report = [&](const RtSetupResult& result) {
    if (result.ok) {
      logger.info("rt: {}", result.message);
    } else {
      logger.warn("rt: {} (continuing without it)", result.message);
      ++refused;
    }
  };
  if (options.lock_memory) report(TryLockMemory());
  if (!options.cpus.empty()) report(TrySetCpuAffinity(options.cpus));
  if (options.fifo_priority != 0) report(TrySetFifoPriority(options.fifo_priority));
  return refused;
}

}  // namespace haptex::runtime
