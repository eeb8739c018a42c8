#include "libs/runtime/shutdown_signal.h"

#include <atomic>
#include <csignal>

namespace haptex::runtime {
namespace {

std::atomic<int> g_signal{0};
std::atomic<bool> g_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free,
              "flags written from a signal handler must be lock-free");

extern "C" void OnShutdownSignal(int signal_number) {
  g_signal.store(signal_number, std::memory_order_relaxed);
  g_requested.store(true, std::memory_order_release);
}

}  // namespace

void InstallShutdownHandlers() {
  struct sigaction action {};
  action.sa_handler = OnShutdownSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: blocking calls return EINTR and loops re-check the flag
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool ShutdownRequested() { return g_requested.load(std::memory_order_acquire); }
void RequestShutdown() { g_requested.store(true, std::memory_order_release); }
int ShutdownSignalNumber() { return g_signal.load(std::memory_order_relaxed); }

}  // namespace haptex::runtime
