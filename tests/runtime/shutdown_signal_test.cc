#include "libs/runtime/shutdown_signal.h"

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>

#include <sys/wait.h>
#include <unistd.h>

namespace haptex::runtime {
namespace {

// Each case runs in a forked child so the process-wide flag starts clear.
int RunInChild(void (*body)()) {
  const pid_t pid = fork();
  if (pid == 0) {
    body();
    std::_Exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

TEST(ShutdownSignalTest, SigtermSetsTheFlagInsteadOfKilling) {
  EXPECT_EQ(RunInChild([] {
              InstallShutdownHandlers();
              if (ShutdownRequested()) std::_Exit(1);
              std::raise(SIGTERM);
              if (!ShutdownRequested()) std::_Exit(2);
              if (ShutdownSignalNumber() != SIGTERM) std::_Exit(3);
            }),
            0);
}

TEST(ShutdownSignalTest, SigintSetsTheFlag) {
  EXPECT_EQ(RunInChild([] {
              InstallShutdownHandlers();
              std::raise(SIGINT);
              if (ShutdownSignalNumber() != SIGINT) std::_Exit(1);
            }),
            0);
}

TEST(ShutdownSignalTest, RequestShutdownWorksWithoutASignal) {
  EXPECT_EQ(RunInChild([] {
              RequestShutdown();
              if (!ShutdownRequested() || ShutdownSignalNumber() != 0) std::_Exit(1);
            }),
            0);
}

TEST(ShutdownSignalTest, WithoutHandlersSigtermKills) {
  // The control case: proves the children above survived because of the handlers.
  EXPECT_EQ(RunInChild([] { std::raise(SIGTERM); }), 128 + SIGTERM);
}

}  // namespace
}  // namespace haptex::runtime
