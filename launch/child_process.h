#pragma once
// One service process: fork + execve with its own environment, stdin /dev/null, stdout and stderr
// appended to a log file and no other file descriptor of the launcher, its own process group (a
// terminal's Ctrl-C reaches the launcher only, which then stops the services in order) and SIGTERM
// when the launcher dies.

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace haptex::launch {

class ChildProcess final {
 public:
  /// Starts argv[0]. Throws std::runtime_error when the log cannot be opened or fork fails; an
  /// executable that cannot be run exits with code 127 (its log says why). `fifo_priority` > 0 runs
  /// it under SCHED_FIFO at that priority (set in the child before exec; a refusal leaves it with
  /// the launcher's policy); 0 keeps the launcher's; < 0 runs it at normal scheduling (SCHED_OTHER).
  ChildProcess(const std::vector<std::string>& argv, const std::vector<std::string>& env, const std::string& log_path,
               int fifo_priority = 0);
  /// Kills a child that still runs (SIGKILL) and reaps it.
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  /// Reaps without waiting: true once the child has exited (then exit_text() says how).
  bool Poll();
  bool exited() const { return status_.has_value(); }
  /// "exit 0", "exit 2", "signal 9".
  std::string exit_text() const;
  void Signal(int signal_number) const;

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
};

}  // namespace haptex::launch
