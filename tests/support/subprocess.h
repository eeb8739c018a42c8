#pragma once
// Real processes for cross-process tests: start, signal, wait with a timeout, read output.

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace haptex::testing {

class Subprocess final {
 public:
  /// Starts argv[0] with argv, the current environment plus `extra_env` ("NAME=value"), and
  /// stdout/stderr written to files in a fresh temporary folder.
  explicit Subprocess(std::vector<std::string> argv, std::vector<std::string> extra_env = {});
  /// Kills the process (SIGKILL) if it still runs.
  ~Subprocess();
  Subprocess(const Subprocess&) = delete;
  Subprocess& operator=(const Subprocess&) = delete;

  pid_t pid() const { return pid_; }
  void Signal(int signal_number) const;
  /// Exit code, or 128 + signal when killed; nullopt when still running after the timeout.
  std::optional<int> WaitFor(std::chrono::milliseconds timeout);
  std::string Stdout() const;
  std::string Stderr() const;

 private:
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
  std::string output_dir_;  // holds stdout and stderr; removed with the object
  std::string stdout_path_;
  std::string stderr_path_;
};

/// How a process that was run to its end ended: exit code (-1: still running after the timeout,
/// then killed) and its output.
struct Finished {
  int code;
  std::string out, err;
};
/// Runs argv to its end (at most `timeout`).
Finished RunToEnd(std::vector<std::string> argv, std::chrono::milliseconds timeout = std::chrono::milliseconds(60000));

/// Contents of a file ("" when missing).
std::string ReadFileOrEmpty(const std::string& path);

}  // namespace haptex::testing
