#include "libs/runtime/rt_setup.h"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>

namespace haptex::runtime {

RtSetupResult TryLockMemory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    return {false, std::string("mlockall failed: ") + std::strerror(errno)};
  }
  return {true, "memory locked"};
}

RtSetupResult TrySetFifoPriority(int priority) {
  if (priority < 1 || priority > 99) {
    return {false, "SCHED_FIFO priority must be 1..99, got " + std::to_string(priority)};
  }
  sched_param param{};
  param.sched_priority = priority;
  const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (error != 0) {
    return {false, "SCHED_FIFO " + std::to_string(priority) + " refused: " + std::strerror(error)};
  }
  return {true, "SCHED_FIFO priority " + std::to_string(priority)};
}

RtSetupResult TrySetCpuAffinity(const std::vector<int>& cpus) {
  if (cpus.empty()) return {false, "no CPU given"};
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  cpu_set_t set;
  CPU_ZERO(&set);
  std::string names;
  for (int cpu : cpus) {
    if (cpu < 0 || cpu >= online) {
      return {false, "CPU " + std::to_string(cpu) + " does not exist (0.." + std::to_string(online - 1) + ")"};
    }
    CPU_SET(cpu, &set);
    names += (names.empty() ? "" : ",") + std::to_string(cpu);
  }
  const int error = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
  if (error != 0) return {false, "affinity refused: " + std::string(std::strerror(error))};
  return {true, "pinned to CPU " + names};
}

}  // namespace haptex::runtime
