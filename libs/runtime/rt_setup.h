#pragma once
// Optional real-time set-up. Each call reports whether it worked and why not; callers warn and
// carry on, so a laptop without privileges still runs.

#include <string>
#include <vector>

namespace haptex::runtime {

struct RtSetupResult {
  bool ok = false;
  std::string message;  // what was done, or why it was not
};

/// mlockall(MCL_CURRENT | MCL_FUTURE): no page faults in hot loops.
RtSetupResult TryLockMemory();
/// The launcher's SCHED_FIFO priority by default: below the kernel's threaded interrupts (50 on a
/// real-time kernel), with room below it for the services' ranks.
inline constexpr int kDefaultFifoPriority = 40;
/// SCHED_FIFO at `priority` (1..99) for the calling thread.
RtSetupResult TrySetFifoPriority(int priority);
/// Pins the calling thread to the given CPUs.
RtSetupResult TrySetCpuAffinity(const std::vector<int>& cpus);

}  // namespace haptex::runtime
