#include "launch/child_process.h"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>

namespace haptex::launch {
namespace {

std::vector<char*> Pointers(std::vector<std::string>& strings) {
  std::vector<char*> pointers;
  for (std::string& s : strings) pointers.push_back(s.data());
  pointers.push_back(nullptr);
  return pointers;
}

}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::vector<std::string>& env,
                           const std::string& log_path, int fifo_priority) {
  // everything the child needs is prepared before fork: after it only async-signal-safe calls
  std::vector<std::string> args = argv, envs = env;
  std::vector<char*> arg_pointers = Pointers(args), env_pointers = Pointers(envs);
  const int log = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log < 0) throw std::runtime_error("cannot write log " + log_path + ": " + std::strerror(errno));
  const pid_t parent = getpid();
  const long open_max = sysconf(_SC_OPEN_MAX);  // for the fallback below (close_range missing)
  const int max_fd = open_max > 0 && open_max < 1 << 20 ? static_cast<int>(open_max) : 1 << 20;
  pid_ = fork();
  if (pid_ < 0) {
    close(log);
    throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  }
  if (pid_ == 0) {
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(126);  // the launcher died before prctl took effect
    const int devnull = open("/dev/null", O_RDONLY);
    if (devnull >= 0) dup2(devnull, 0);
    dup2(log, 1);
    dup2(log, 2);
    // Only 0-2 cross exec: the launcher's sockets (its Health socket), the other services' logs
    // and whatever else it holds stay behind, close-on-exec or not.
    if (close_range(3, ~0U, 0) != 0) {
      for (int fd = 3; fd < max_fd; ++fd) close(fd);
    }
    if (fifo_priority > 0) {
      sched_param param{};
      param.sched_priority = fifo_priority;
      sched_setscheduler(0, SCHED_FIFO, &param);  // refused: the launcher's policy stays
    } else if (fifo_priority < 0) {
      sched_param param{};  // a real-time launcher's child would inherit its policy
      sched_setscheduler(0, SCHED_OTHER, &param);
    }
    // the launcher's signal dispositions are not the service's
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    signal(SIGPIPE, SIG_DFL);
    execve(arg_pointers[0], arg_pointers.data(), env_pointers.data());
    static const char message[] = "haptex launch: cannot execute the service\n";
    (void)!write(2, message, sizeof(message) - 1);
    _exit(127);
  }
  close(log);
  setpgid(pid_, pid_);  // also from the parent, so no signal races the child's own call
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && !exited()) {
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
}

bool ChildProcess::Poll() {
  if (exited()) return true;
  int status = 0;
  const pid_t r = waitpid(pid_, &status, WNOHANG);
  if (r == pid_) status_ = status;
  return exited();
}

std::string ChildProcess::exit_text() const {
  if (!status_) return "running";
  if (WIFEXITED(*status_)) return "exit " + std::to_string(WEXITSTATUS(*status_));
  if (WIFSIGNALED(*status_)) return "signal " + std::to_string(WTERMSIG(*status_));
  return "ended";
}

void ChildProcess::Signal(int signal_number) const {
  if (pid_ > 0 && !exited()) kill(pid_, signal_number);
}

}  // namespace haptex::launch
